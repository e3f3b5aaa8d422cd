// The static torque flow of a train and the train's operating limits (the schema-1 limits of
// gearbox_spec_limits.cc stated on the train's input shaft, loads and first mesh).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "gearnvh/model/count_text.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"
#include "train_rules.h"

namespace gearnvh {
namespace {

using L = GearboxLimits;

double BodySpeed(const TrainTopology& t, int body) {
  return std::abs(t.bodies[static_cast<size_t>(body)].speed);
}

double SpeedRatio(const TrainTopology& t, int body) {
  return std::abs(t.bodies[static_cast<size_t>(body)].speed_ratio);
}

std::string MeshName(const TrainSpec& spec, size_t m) {
  return "meshes[" + std::to_string(m) + "] (" + spec.meshes[m].Name() + ")";
}

}  // namespace

void RequireTrainSize(const TrainSpec& spec) {
  const auto at_most = [](const char* path, size_t count, size_t limit, const char* one,
                          const char* many) {
    if (count <= limit) return;
    throw InputError(path, 0, Count(static_cast<long>(count), one, many),
                     fmt::format("must have at most {} {}: checking a train builds dense models of "
                                 "all its bodies and meshes, whose time and memory grow with their "
                                 "number squared or faster (1000 meshes ran past 2 GB)",
                                 limit, many));
  };
  at_most("shafts", spec.shafts.size(), L::kMaxTrainShafts, "shaft", "shafts");
  at_most("gears", spec.gears.size(), L::kMaxTrainGears, "gear", "gears");
  at_most("meshes", spec.meshes.size(), L::kMaxTrainMeshes, "mesh", "meshes");
}

void RequireUniqueBodyNames(const TrainSpec& spec) {
  for (const TrainGear& g : spec.gears) {
    if (spec.FindShaft(g.name) == nullptr) continue;
    throw InputError("gears." + g.name, 0, "'" + g.name + "'",
                     "has the name of shafts." + g.name +
                         ": a name belongs to one shaft or one gear (a load's `on` names either)");
  }
}

void RequireMeshesPerGear(const TrainSpec& spec) {
  for (const TrainGear& g : spec.gears) {
    std::string meshes;
    size_t count = 0;
    for (size_t m = 0; m < spec.meshes.size(); ++m) {
      if (spec.meshes[m].gear_a != g.name && spec.meshes[m].gear_b != g.name) continue;
      ++count;
      if (count <= 3)
        meshes += (meshes.empty() ? "" : ", ") + ("meshes[" + std::to_string(m) + "]");
    }
    if (count <= L::kMaxMeshesPerGear) continue;
    throw InputError("gears." + g.name, 0,
                     Count(static_cast<long>(count), "mesh", "meshes") + " (" + meshes + ", ...)",
                     fmt::format("may take part in at most {} meshes (a planet set's sun has about "
                                 "7): each mesh of a gear multiplies the contact states the model "
                                 "follows",
                                 L::kMaxMeshesPerGear));
  }
}

// The normal module of mesh m (its two gears share it: ValidateTrainSpec).
double NormalModule(const TrainSpec& spec, size_t m) {
  return spec.FindGear(spec.meshes[m].gear_a)->gear.module;
}

void RequireSharedCenterDistances(const TrainSpec& spec, const TrainTopology& topology) {
  std::vector<double> distance(spec.meshes.size());
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    const TrainGear& a = *spec.FindGear(spec.meshes[m].gear_a);
    const TrainGear& b = *spec.FindGear(spec.meshes[m].gear_b);
    distance[m] =
        ComputePairGeometry(MeshGearbox(spec, topology, static_cast<int>(m), 0.0)).center_distance;
    for (size_t e = 0; e < m; ++e) {
      const TrainGear& ea = *spec.FindGear(spec.meshes[e].gear_a);
      const TrainGear& eb = *spec.FindGear(spec.meshes[e].gear_b);
      const bool same_shafts = (ea.shaft == a.shaft && eb.shaft == b.shaft) ||
                               (ea.shaft == b.shaft && eb.shaft == a.shaft);
      const double tolerance = L::kCenterDistanceTolerancePerModule *
                               std::min(NormalModule(spec, m), NormalModule(spec, e));
      if (!same_shafts || std::abs(distance[e] - distance[m]) <= tolerance) {
        continue;
      }
      const std::string p = "meshes[" + std::to_string(m) + "]";
      const bool written = spec.meshes[m].mesh.center_distance.has_value();
      throw InputError(
          p + (written ? ".center_distance" : ".gears"), 0,
          written ? InputError::Text{"{}", {InputError::Length(distance[m])}}
                  : InputError::Text{"[" + a.name + ", " + b.name + "]"},
          {"joins shafts '" + a.shaft + "' and '" + b.shaft + "' at a centre distance of {}, but " +
               MeshName(spec, e) +
               " joins them at {}: the meshes between two shafts share the shafts' one centre "
               "distance (give them the same center_distance, with profile shifts that fit it)",
           {InputError::Length(distance[m], p + ".center_distance"),
            InputError::Length(distance[e], "meshes[" + std::to_string(e) + "].center_distance")}});
    }
  }
}

LoadAction ActionOfLoad(const TrainSpec& spec, const TrainTopology& topology, size_t load_index) {
  const TrainLoad& load = spec.operating.loads[load_index];
  const auto body_of = [&](const std::string& name) {
    const int shaft = spec.ShaftIndex(name);
    return shaft >= 0 ? shaft : topology.gear_body[static_cast<size_t>(spec.GearIndex(name))];
  };
  const auto speed = [&](int body) { return topology.bodies[static_cast<size_t>(body)].speed; };
  const auto sense = [&](int body) { return speed(body) > 0.0 ? 1.0 : -1.0; };
  const int body = body_of(load.on);
  // Relative to a fixed shaft is relative to the housing: the reaction does no work there.
  const int other = load.relative_to.empty() || speed(body_of(load.relative_to)) == 0.0
                        ? -1
                        : body_of(load.relative_to);
  LoadAction a;
  a.viscous = load.viscous;
  a.relative_speed = speed(body) - (other >= 0 ? speed(other) : 0.0);
  // Two bodies at one nominal speed (a ratio such as 20/30 x 30/20, one rounding apart): 0.
  if (other >= 0 && std::abs(a.relative_speed) <=
                        1e-9 * std::max(std::abs(speed(body)), std::abs(speed(other)))) {
    a.relative_speed = 0.0;
  }
  const double along = a.relative_speed > 0.0 ? 1.0 : a.relative_speed < 0.0 ? -1.0 : 0.0;
  const double drag = along * (load.torque + load.viscous * std::abs(a.relative_speed));
  a.terms.push_back({body, sense(body) * drag, sense(body)});
  if (other >= 0) a.terms.push_back({other, -sense(other) * drag, -sense(other)});
  return a;
}

bool DragDampsFreeRotation(const TrainSpec& spec, const TrainTopology& topology) {
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    if (ActionOfLoad(spec, topology, i).DampsFreeRotation()) return true;
  }
  return false;
}

TrainTorqueFlow StaticTorqueFlow(const TrainSpec& spec, const TrainTopology& topology) {
  const size_t meshes = spec.meshes.size();
  TrainTorqueFlow flow;
  flow.transmitted_torque.assign(meshes, 0.0);
  flow.back_flank_loaded.assign(meshes, false);
  flow.main_load.assign(meshes, -1);
  std::vector<double> main_power(meshes, 0.0);
  std::vector<double> mesh_power(meshes, 0.0);
  std::vector<bool> far_is_a(meshes, false);  // the side away from the input is gear a's
  std::vector<double> coupling_power(spec.couplings.size(), 0.0);  // from shaft_a to shaft_b
  double total_power = 0.0;
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    std::vector<double> power_of_load(meshes, 0.0);  // this load's net power through each mesh
    for (const LoadAction::Term& term : ActionOfLoad(spec, topology, i).terms) {
      // Power per unit input speed: without viscous drag the flow is the same bits at every
      // input speed (the reaction of a relative drag sends power back: negative).
      const double power = term.resisting * SpeedRatio(topology, term.body);
      total_power += power;
      // Up the spanning tree to the input: every mesh and coupling on the way carries this power.
      for (int child = term.body, parent; (parent = topology.ParentBody(spec, child)) >= 0;
           child = parent) {
        const int coupling = topology.parent_coupling[static_cast<size_t>(child)];
        if (coupling >= 0) {
          // The far side is the child: power flows to it from the parent.
          const bool to_b = spec.ShaftIndex(spec.couplings[static_cast<size_t>(coupling)].shaft_b) ==
                            child;
          coupling_power[static_cast<size_t>(coupling)] += to_b ? power : -power;
          continue;
        }
        const auto m = static_cast<size_t>(topology.parent_mesh[static_cast<size_t>(child)]);
        mesh_power[m] += power;
        power_of_load[m] += power;
        far_is_a[m] =  // the same for every load through m (a tree)
            child == topology.gear_body[static_cast<size_t>(spec.GearIndex(spec.meshes[m].gear_a))];
      }
    }
    for (size_t m = 0; m < meshes; ++m) {
      if (std::abs(power_of_load[m]) > main_power[m]) {
        main_power[m] = std::abs(power_of_load[m]);
        flow.main_load[m] = static_cast<int>(i);
      }
    }
  }
  flow.input_torque = total_power;  // the input's speed ratio is 1
  for (size_t c = 0; c < spec.couplings.size(); ++c) {
    flow.coupling_torque.push_back(
        coupling_power[c] / SpeedRatio(topology, spec.ShaftIndex(spec.couplings[c].shaft_a)));
  }
  for (size_t m = 0; m < meshes; ++m) {
    const int body_b =
        topology.gear_body[static_cast<size_t>(spec.GearIndex(spec.meshes[m].gear_b))];
    // Power P through the mesh at base-circle speed |w_b| r_b,b: torque on gear b P / |w_b|. It
    // flows from gear b to a (the back flank) when it flows to a's side, or back from b's side
    // (a relative drag's reaction).
    flow.transmitted_torque[m] = std::abs(mesh_power[m]) / SpeedRatio(topology, body_b);
    flow.back_flank_loaded[m] =
        mesh_power[m] > 0.0 ? far_is_a[m] : mesh_power[m] < 0.0 && !far_is_a[m];
  }
  return flow;
}

double FirstMeshFrequency(const TrainSpec& spec, const TrainTopology& topology,
                          double input_speed) {
  const TrainMesh& first = spec.meshes.front();
  const int teeth_a = spec.FindGear(first.gear_a)->gear.teeth;
  const int body_a = topology.gear_body[static_cast<size_t>(spec.GearIndex(first.gear_a))];
  const double speed_ratio = BodySpeed(topology, body_a) / spec.operating.speed;
  return teeth_a * speed_ratio * input_speed / (2.0 * std::numbers::pi);
}

FastestMesh FastestPitchLine(const TrainSpec& spec, const TrainTopology& topology) {
  FastestMesh fastest;
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    const TrainMesh& mesh = spec.meshes[m];
    const int body_a = topology.gear_body[static_cast<size_t>(spec.GearIndex(mesh.gear_a))];
    const double v = BodySpeed(topology, body_a) / spec.operating.speed *
                     PitchRadius(spec.FindGear(mesh.gear_a)->gear);
    if (v > fastest.velocity_per_speed) {
      fastest.velocity_per_speed = v;
      fastest.name = "meshes[" + std::to_string(m) + "] (" + mesh.Name() + ")";
    }
  }
  return fastest;
}

int ExcitationBody(const TrainSpec& spec, const TrainTopology& topology, size_t order) {
  const std::string& on = spec.operating.excitation[order].on;
  return on.empty() ? topology.input_body : spec.ShaftIndex(on);
}

double ExcitationOrderOfInput(const TrainSpec& spec, const TrainTopology& topology, size_t order) {
  return spec.operating.excitation[order].order *
         SpeedRatio(topology, ExcitationBody(spec, topology, order));
}

void RequireExcitationWithinSpeed(const TrainSpec& spec, const TrainTopology& topology) {
  const TrainOperating& op = spec.operating;
  const std::vector<double> inertia =
      op.excitation.empty() ? std::vector<double>{} : BodyInertias(spec, topology);
  for (size_t i = 0; i < op.excitation.size(); ++i) {
    const ExcitationOrder& e = op.excitation[i];
    const int body = ExcitationBody(spec, topology, i);
    const double speed = std::abs(topology.bodies[static_cast<size_t>(body)].speed);
    const std::string shaft = (body == topology.input_body ? "input shaft '" : "shaft '") +
                              topology.bodies[static_cast<size_t>(body)].name + "'";
    // The speed fluctuation a / (k W_s) the shaft would have on its own: a torque order's a = T /
    // J_s (one rule for both kinds; coupled to the rest, the shaft swings less).
    const bool torque = e.kind == ExcitationKind::kTorque;
    const double acceleration =
        torque ? e.amplitude / inertia[static_cast<size_t>(body)] : e.amplitude;
    const double fluctuation = acceleration / (e.order * speed);
    if (fluctuation <= speed) continue;
    throw InputError(
        "operating.excitation[" + std::to_string(i) + "].amplitude", 0,
        MessageNumber(e.amplitude) + (torque ? " N m" : " rad/s^2"),
        fmt::format(
            "makes the speed fluctuation {} = {} of the {} exceed its mean speed {}: the "
            "shaft would turn backwards, and the model assumes a steady mean speed",
            torque ? "T / (J order x speed), J the shaft's polar inertia," : "a / (order x speed)",
            InUnit(fluctuation, op.speed_unit), shaft, InUnit(speed, op.speed_unit)));
  }
  // One shaft and kind per frequency: orders are summed per shaft, and two shafts' orders at one
  // frequency would share one oscillator of the exact solver's inputs.
  for (size_t i = 0; i < op.excitation.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      const double fi = ExcitationOrderOfInput(spec, topology, i),
                   fj = ExcitationOrderOfInput(spec, topology, j);
      if (std::abs(fi - fj) > 1e-9 * fi) continue;
      const ExcitationOrder &a = op.excitation[i], &b = op.excitation[j];
      if (ExcitationBody(spec, topology, i) == ExcitationBody(spec, topology, j) &&
          a.kind == b.kind)
        continue;
      throw InputError(
          "operating.excitation[" + std::to_string(i) + "].order", 0, MessageNumber(a.order),
          fmt::format("has the frequency of operating.excitation[{}] ({:.6g} x the input shaft's "
                      "speed) but another shaft or kind: orders at one frequency act on one "
                      "shaft, as one kind (give them as one order)",
                      j, fi));
    }
  }
}

void RequireTrainToothLoads(const TrainSpec& spec, const TrainTopology& topology) {
  const TrainOperating& op = spec.operating;
  const TrainTorqueFlow flow = StaticTorqueFlow(spec, topology);
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    const TrainGear& a = *spec.FindGear(spec.meshes[m].gear_a);
    const TrainGear& b = *spec.FindGear(spec.meshes[m].gear_b);
    const double unit_load = ToothUnitLoad(a.gear, b.gear, flow.transmitted_torque[m]);
    if (unit_load <= L::kMaxUnitLoad) continue;
    const int load = flow.main_load[m];  // power flows, so some load sends it
    const TrainLoad& main = op.loads[static_cast<size_t>(load)];
    // Named at its viscous drag when that is the larger part of its mean torque.
    const bool viscous =
        main.viscous *
            std::abs(ActionOfLoad(spec, topology, static_cast<size_t>(load)).relative_speed) >
        main.torque;
    throw InputError(
        "operating.loads[" + std::to_string(load) + (viscous ? "].viscous" : "].torque"), 0,
        viscous ? MessageNumber(main.viscous) + " N m s/rad" : MessageNumber(main.torque) + " N m",
        fmt::format("gives meshes[{}] ({}-{}) a tooth load of {:.3g} N/um of face width "
                    "(transmitted torque {:.6g} N m on {}), above {} N/um: the mesh-stiffness and "
                    "LSTE models assume small linear-elastic tooth deflections, and real teeth "
                    "yield long before",
                    m, a.name, b.name, unit_load * 1e-6, flow.transmitted_torque[m], b.name,
                    L::kMaxUnitLoad * 1e-6));
  }
}

void ValidateTrainLimits(const TrainSpec& spec, const TrainTopology& topology) {
  const TrainOperating& op = spec.operating;
  const double omega_in = op.speed;
  // Load: a linear-elastic tooth model, per mesh at the torque it transmits.
  RequireTrainToothLoads(spec, topology);

  RequireExcitationWithinSpeed(spec, topology);

  // Speed: the pitch-line velocity of every mesh (a written speed sweep: checked by the loader).
  const FastestMesh fastest = FastestPitchLine(spec, topology);
  RequirePitchLineVelocity("operating.speed.value", omega_in, op.speed_unit,
                           fastest.velocity_per_speed, fastest.name);

  // Run length: analysis.cycles and transient_cycles count cycles of the first mesh, whose mesh
  // frequency is z_a |w_a| / 2 pi with |w_a| in proportion to the input speed.
  const AnalysisSpec& an = spec.analysis;
  for (const auto& [speed, path] : {std::pair{omega_in, "operating.speed.value"},
                                    std::pair{an.speed_sweep.from, "analysis.speed_sweep.from"}}) {
    const double hz = FirstMeshFrequency(spec, topology, speed);
    const double seconds = static_cast<double>(an.cycles + an.transient_cycles) / hz;
    if (!(seconds <= L::kMaxSimulatedSeconds)) {
      throw InputError(
          path, 0, MessageNumber(speed),
          fmt::format("is so low that the {} cycles of the first mesh (meshes[0], "
                      "analysis.cycles + transient_cycles) last {:.3g} s of simulated "
                      "time (mesh frequency {:.3g} Hz); the limit is {} s",
                      an.cycles + an.transient_cycles, seconds, hz, L::kMaxSimulatedSeconds));
    }
  }
}

}  // namespace gearnvh
