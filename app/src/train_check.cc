#include "train_check.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

namespace gearnvh::app {
namespace {

constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);

struct CriticalSpeed {
  int mode = 0;            // numbered from 1
  std::string line;        // "mesh g1-g2 1x", "shaft input 1x"
  double input_speed = 0.0;  // rad/s of the input shaft
};

// Input speeds at which an order line crosses a mode: mesh i harmonic h at frequency
// h z_a |w_a| / 2 pi, shaft j at |w_j| / 2 pi, both proportional to the input speed.
std::vector<CriticalSpeed> CriticalSpeeds(const TrainSpec& spec, const GearTrain& train,
                                          const TrainTorsionalModes& modes) {
  std::vector<CriticalSpeed> out;
  const double w_in = std::abs(train.topology.bodies[static_cast<size_t>(train.topology.input_body)].speed);
  for (size_t k = 0; k < modes.frequencies_hz.size(); ++k) {
    const double w_mode = 2.0 * std::numbers::pi * modes.frequencies_hz[k];
    for (const TrainMeshModel& mesh : train.meshes) {
      const double ratio = std::abs(train.topology.bodies[static_cast<size_t>(mesh.body_a)].speed) / w_in;
      const int z = spec.gears[static_cast<size_t>(mesh.gear_a)].gear.teeth;
      for (int h = 1; h <= 3; ++h) {
        out.push_back({static_cast<int>(k) + 1, fmt::format("mesh {} {}x", mesh.name, h),
                       w_mode / (h * z * ratio)});
      }
    }
    for (const TrainBody& body : train.topology.bodies) {
      if (body.kind != BodyKind::kShaft) continue;
      out.push_back({static_cast<int>(k) + 1, fmt::format("shaft {} 1x", body.name),
                     w_mode / (std::abs(body.speed) / w_in)});
    }
  }
  return out;
}

const char* KindName(BodyKind kind) { return kind == BodyKind::kShaft ? "shaft" : "loose gear"; }

}  // namespace

nlohmann::json TrainCheckReport(const TrainSpec& spec, const GearTrain& train,
                                const TrainTorsionalModes& modes) {
  nlohmann::json doc;
  doc["name"] = spec.name;
  doc["schema"] = "gearnvh/2";
  doc["meshes"] = nlohmann::json::array();
  for (const TrainMeshModel& m : train.meshes) {
    const PairGeometry& g = m.geometry;
    nlohmann::json geometry = {{"contact_ratio", g.contact_ratio},
                               {"center_distance", g.center_distance},
                               {"working_pressure_angle", g.working_pressure_angle},
                               {"base_pitch", g.base_pitch},
                               {"gear_ratio", g.gear_ratio},
                               {"mesh_frequency_hz", g.mesh_frequency_hz}};
    if (g.helix_angle > 0.0) {
      geometry["helix_angle"] = g.helix_angle;
      geometry["base_helix_angle"] = g.base_helix_angle;
      geometry["overlap_ratio"] = g.overlap_ratio;
      geometry["total_contact_ratio"] = g.total_contact_ratio;
    }
    const MeshStiffnessSummary& k = m.stiffness;
    doc["meshes"].push_back(
        {{"name", m.name},
         {"gears", {spec.gears[static_cast<size_t>(m.gear_a)].name,
                    spec.gears[static_cast<size_t>(m.gear_b)].name}},
         {"geometry", geometry},
         {"transmitted_torque", m.transmitted_torque},
         {"load", m.cycle.load},
         {"back_flank_loaded", m.back_flank_loaded},
         {"stiffness_model", m.cycle.overridden ? "override" : "potential_energy"},
         {"stiffness",
          {{"mean", k.mean},
           // null when a single pair never carries the load alone (total contact ratio >= 2)
           {"single_pair_mean",
            k.single_pair_mean > 0.0 ? nlohmann::json(k.single_pair_mean) : nlohmann::json()},
           {"min", k.min},
           {"max", k.max}}},
         {"lste_peak_to_peak", k.lste_peak_to_peak},
         {"load_sharing_max", k.load_sharing_max}});
  }
  doc["bodies"] = nlohmann::json::array();
  for (size_t b = 0; b < train.topology.bodies.size(); ++b) {
    const TrainBody& body = train.topology.bodies[b];
    nlohmann::json gears = nlohmann::json::array();
    for (int g : body.gears) gears.push_back(spec.gears[static_cast<size_t>(g)].name);
    doc["bodies"].push_back({{"name", body.name},
                             {"kind", KindName(body.kind)},
                             {"gears", gears},
                             {"speed", body.speed},
                             {"speed_rpm", body.speed * kRpm},
                             {"polar_inertia", train.body_inertia[b]}});
  }
  doc["input_torque"] = train.input_torque;
  nlohmann::json critical = nlohmann::json::array();
  for (const CriticalSpeed& c : CriticalSpeeds(spec, train, modes)) {
    critical.push_back({{"mode", c.mode},
                        {"line", c.line},
                        {"input_speed", c.input_speed},
                        {"input_speed_rpm", c.input_speed * kRpm}});
  }
  doc["tiers"] = nlohmann::json::array({{{"name", "tier 1"},
                                         {"dof", train.body_inertia.size()},
                                         {"free_rotations", modes.free_rotations},
                                         {"natural_frequencies_hz", modes.frequencies_hz}}});
  doc["critical_speeds"] = critical;
  doc["tiers_unavailable"] = {"tier 2", "tier 3", "tier 4", "tier 5", "N20 simple", "N20 MTA"};
  doc["warnings"] = train.warnings;
  return doc;
}

void PrintTrainCheck(const std::string& file, const TrainSpec& spec, const GearTrain& train,
                     const TrainTorsionalModes& modes) {
  fmt::print("{}  ({}, gear train: {} shafts, {} gears, {} meshes)\n", spec.name, file,
             spec.shafts.size(), spec.gears.size(), spec.meshes.size());
  fmt::print("  {:<16}{:>12}{:>8}{:>8}{:>9}{:>9}{:>10}{:>12}{:>12}\n", "mesh", "torque",
             "eps_a", "eps_b", "eps_g", "f_mesh", "k_mean", "k_single", "LSTE p-p");
  // Width-padded by bytes: each µ is two bytes, so its column is one wider.
  fmt::print("  {:<16}{:>12}{:>8}{:>8}{:>9}{:>9}{:>11}{:>13}{:>13}\n", "", "[N m]", "", "", "",
             "[Hz]", "[N/µm]", "[N/µm]", "[µm]");
  for (const TrainMeshModel& m : train.meshes) {
    const PairGeometry& g = m.geometry;
    const std::string single = m.stiffness.single_pair_mean > 0.0
                                   ? fmt::format("{:.1f}", m.stiffness.single_pair_mean * 1e-6)
                                   : "-";  // never one pair alone
    fmt::print("  {:<16}{:>12.4g}{:>8.4f}{:>8.4f}{:>9.4f}{:>9.1f}{:>10.1f}{:>12}{:>12.4f}{}\n",
               m.name, m.transmitted_torque, g.contact_ratio, g.overlap_ratio,
               g.total_contact_ratio, g.mesh_frequency_hz, m.stiffness.mean * 1e-6, single,
               m.stiffness.lste_peak_to_peak * 1e6,
               g.helix_angle > 0.0 ? fmt::format("  helical {:.1f}°", g.helix_angle * 180.0 /
                                                                        std::numbers::pi)
                                   : "  spur");
  }
  fmt::print("  {:<16}{:<12}{:>14}{:>18}   gears\n", "body", "kind", "speed [rpm]",
             "J [kg m²]");
  for (size_t b = 0; b < train.topology.bodies.size(); ++b) {
    const TrainBody& body = train.topology.bodies[b];
    std::string gears;
    for (int g : body.gears) gears += (gears.empty() ? "" : ", ") + spec.gears[static_cast<size_t>(g)].name;
    fmt::print("  {:<16}{:<12}{:>14.2f}{:>18.4e}   {}\n", body.name, KindName(body.kind),
               body.speed * kRpm, train.body_inertia[b], gears);
  }
  fmt::print("  input torque balancing the loads: {:.4g} N m\n", train.input_torque);
  fmt::print("  tier 1 (torsional, {} DOF, {} free rotation{}): natural frequencies [Hz]\n   ",
             train.body_inertia.size(), modes.free_rotations, modes.free_rotations == 1 ? "" : "s");
  for (double f : modes.frequencies_hz) fmt::print(" {:.1f}", f);
  const SweepRange& sweep = spec.analysis.speed_sweep;
  fmt::print("\n  critical input speeds, mesh order 1, within the speed sweep {:.0f}-{:.0f} rpm:\n",
             sweep.from * kRpm, sweep.to * kRpm);
  for (const CriticalSpeed& c : CriticalSpeeds(spec, train, modes)) {
    if (c.line.find("mesh") == 0 && c.line.find(" 1x") != std::string::npos &&
        c.input_speed >= sweep.from && c.input_speed <= sweep.to) {
      fmt::print("    mode {:<3} {:<28}{:>12.1f}\n", c.mode, c.line, c.input_speed * kRpm);
    }
  }
  fmt::print("  tiers 2-5 and N20 of a train are not built yet: tier 1 only\n");
  for (const std::string& w : train.warnings) fmt::print("  warning: {}\n", w);
}

}  // namespace gearnvh::app
