#include "gearnvh/model/train_spec.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <set>
#include <stdexcept>

#include "gearnvh/model/count_text.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "train_rules.h"

namespace gearnvh {
namespace {

std::string MeshPath(int m) { return "meshes[" + std::to_string(m) + "]"; }

// Replaces the schema-1 prefix of an error path found on a mesh's gearbox by the train's.
std::string TrainPath(const std::string& path, const TrainSpec& spec, int m) {
  const TrainMesh& mesh = spec.meshes[static_cast<size_t>(m)];
  const TrainGear& a = *spec.FindGear(mesh.gear_a);
  const TrainGear& b = *spec.FindGear(mesh.gear_b);
  // Schema 1 places a shaft's gear with `gear_at`; schema 2 with the gear's own `at`.
  const std::vector<std::pair<std::string, std::string>> prefixes{
      {"shafts.input.gear_at", "gears." + a.name + ".at"},
      {"shafts.output.gear_at", "gears." + b.name + ".at"},
      {"gears.pinion", "gears." + a.name},
      {"gears.wheel", "gears." + b.name},
      {"mesh", MeshPath(m)},
      {"shafts.input", "shafts." + a.shaft},
      {"shafts.output", "shafts." + b.shaft},
      {"operating.torque", "operating.loads"}};
  for (const auto& [from, to] : prefixes) {
    if (path.compare(0, from.size(), from) == 0 &&
        (path.size() == from.size() || path[from.size()] == '.' || path[from.size()] == '[')) {
      return to + path.substr(from.size());
    }
  }
  return path;
}

// The schema-1 gear names a pair rule's text may mention ("the module of gears.pinion"), as the
// train's gears.
std::string TrainRule(std::string rule, const TrainSpec& spec, int m) {
  const TrainMesh& mesh = spec.meshes[static_cast<size_t>(m)];
  for (const auto& [from, to] : {std::pair{std::string("gears.pinion"), "gears." + mesh.gear_a},
                                 std::pair{std::string("gears.wheel"), "gears." + mesh.gear_b}}) {
    for (size_t at = rule.find(from); at != std::string::npos; at = rule.find(from, at)) {
      rule.replace(at, from.size(), to);
      at += to.size();
    }
  }
  return rule;
}

// The speed a mesh or coupling would give a body: its parent edge on the spanning tree, or a mesh
// or coupling closing a loop onto it.
struct SpeedClaim {
  int mesh = -1;  // -1 and coupling -1: the input shaft's own speed
  int body = 0;
  double speed = 0.0;
  int coupling = -1;
  bool Own() const { return mesh < 0 && coupling < 0; }
  std::string Path(const TrainSpec& spec) const {
    return mesh >= 0      ? MeshPath(mesh)
           : coupling < 0 ? "the input speed"
                          : "couplings." + spec.couplings[static_cast<size_t>(coupling)].name;
  }
};

bool SameSpeed(double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(a); }

// Every loop closes with consistent ratios. Of the speeds a body is given (by its tree edge and by
// the meshes and couplings closing loops onto it), the one most of them agree on stands (the
// tree's on a tie; the input's own speed always), and the first edge giving another is named: the
// odd one out of several parallel meshes, not the first one the tree happened to take.
void RequireConsistentLoops(const TrainSpec& spec, const TrainTopology& t,
                            const std::vector<SpeedClaim>& loop_claims) {
  for (const SpeedClaim& odd : loop_claims) {
    const TrainBody& body = t.bodies[static_cast<size_t>(odd.body)];
    if (SameSpeed(body.speed, odd.speed)) continue;
    std::vector<SpeedClaim> claims{{t.parent_mesh[static_cast<size_t>(odd.body)], odd.body,
                                    body.speed, t.parent_coupling[static_cast<size_t>(odd.body)]}};
    for (const SpeedClaim& c : loop_claims) {
      if (c.body == odd.body) claims.push_back(c);
    }
    const auto agreeing = [&](const SpeedClaim& a) {
      return std::count_if(claims.begin(), claims.end(),
                           [&](const SpeedClaim& b) { return SameSpeed(a.speed, b.speed); });
    };
    const SpeedClaim* standing = &claims.front();
    if (!standing->Own()) {
      for (const SpeedClaim& c : claims) {
        if (agreeing(c) > agreeing(*standing)) standing = &c;
      }
    }
    const auto found = std::find_if(claims.begin(), claims.end(), [&](const SpeedClaim& c) {
      return !SameSpeed(standing->speed, c.speed);
    });
    const SpeedClaim& offender = found == claims.end() ? odd : *found;
    std::string others;
    for (const SpeedClaim& c : claims) {
      if (!SameSpeed(standing->speed, c.speed)) continue;
      others += (others.empty() ? "" : ", ") + c.Path(spec);
    }
    const std::string rule =
        "closes a kinematic loop whose ratios disagree: it would turn '" + body.name + "' at " +
        InUnit(offender.speed, spec.operating.speed_unit) + ", the other path (" + others +
        ") at " + InUnit(standing->speed, spec.operating.speed_unit);
    if (offender.coupling >= 0 && offender.mesh < 0) {
      const TrainCoupling& c = spec.couplings[static_cast<size_t>(offender.coupling)];
      throw InputError(offender.Path(spec) + ".between", 0,
                       "[" + c.shaft_a + ", " + c.shaft_b + "]",
                       rule + " (a coupling joins shafts turning at one speed)");
    }
    const TrainMesh& mesh = spec.meshes[static_cast<size_t>(offender.mesh)];
    throw InputError(MeshPath(offender.mesh) + ".gears", 0,
                     "[" + mesh.gear_a + ", " + mesh.gear_b + "]", rule);
  }
}

// A fixed shaft stands: it is not the input, no coupling joins it, and none of its fixed gears
// meshes (a loose gear on it may: it turns on the stationary shaft).
void RequireStationaryShaftsStill(const TrainSpec& spec, const TrainTopology& t) {
  for (const TrainCoupling& c : spec.couplings) {
    for (const std::string& name : {c.shaft_a, c.shaft_b}) {
      const TrainShaft* shaft = spec.FindShaft(name);  // RequireValidCouplings ran before
      if (shaft == nullptr || !shaft->fixed) continue;
      throw InputError("couplings." + c.name + ".between", 0,
                       "[" + c.shaft_a + ", " + c.shaft_b + "]",
                       "joins the fixed shaft '" + name + "' (shafts." + name +
                           ".fixed: true), which does not turn: a coupling joins two turning "
                           "shafts");
    }
  }
  const TrainShaft& input = spec.shafts[static_cast<size_t>(t.input_body)];
  if (input.fixed) {
    throw InputError(
        "operating.speed.shaft", 0, "'" + input.name + "'",
        "names a fixed shaft (shafts." + input.name + ".fixed: true): the input shaft turns");
  }
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    const TrainMesh& mesh = spec.meshes[m];
    for (const std::string& name : {mesh.gear_a, mesh.gear_b}) {
      const TrainGear& gear = *spec.FindGear(name);
      if (gear.mounting == Mounting::kLoose || !spec.FindShaft(gear.shaft)->fixed) continue;
      throw InputError(MeshPath(static_cast<int>(m)) + ".gears", 0,
                       "[" + mesh.gear_a + ", " + mesh.gear_b + "]",
                       "meshes gear '" + name + "', fixed on the fixed shaft '" + gear.shaft +
                           "' (shafts." + gear.shaft +
                           ".fixed: true), which does not turn: a gear that meshes on a "
                           "stationary shaft must be mounted loose");
    }
  }
}

// The breadth-first search of AnalyseTrainTopology from the input body over the meshes; a coupling
// only reaches a shaft the meshes do not (then the meshes go on from it), so that a coupling in
// parallel with a gear path is the loop's edge and the gears carry the static torque.
class SpeedSearch {
 public:
  SpeedSearch(const TrainSpec& spec, TrainTopology& t) : spec_(spec), t_(t), queue_{t.input_body} {}
  void Run() {
    do {
      Meshes();
    } while (Coupling());
  }
  // The couplings between shafts reached otherwise: they close a loop (their speed claims join
  // claims()).
  std::vector<int> LoopCouplings() {
    std::vector<int> out;
    for (size_t c = 0; c < spec_.couplings.size(); ++c) {
      const int ba = spec_.ShaftIndex(spec_.couplings[c].shaft_a);
      const int bb = spec_.ShaftIndex(spec_.couplings[c].shaft_b);
      if (couplings_.count(static_cast<int>(c)) > 0 || !Reached(ba) || !Reached(bb)) continue;
      out.push_back(static_cast<int>(c));
      claims_.push_back({-1, bb, t_.bodies[static_cast<size_t>(ba)].speed, static_cast<int>(c)});
    }
    return out;
  }
  // The speeds the meshes (and couplings) closing loops give the bodies they reach.
  const std::vector<SpeedClaim>& claims() const { return claims_; }

 private:
  bool Reached(int body) const { return t_.parent_mesh[static_cast<size_t>(body)] != -2; }

  // Empties the queue through the meshes: omega_b = -omega_a z_a / z_b.
  void Meshes() {
    while (!queue_.empty()) {
      const int body = queue_.front();
      queue_.pop_front();
      for (size_t m = 0; m < spec_.meshes.size(); ++m) {
        const TrainMesh& mesh = spec_.meshes[m];
        const int ga = spec_.GearIndex(mesh.gear_a), gb = spec_.GearIndex(mesh.gear_b);
        const int ba = t_.gear_body[static_cast<size_t>(ga)],
                  bb = t_.gear_body[static_cast<size_t>(gb)];
        if ((ba != body && bb != body) || meshes_.count(static_cast<int>(m)) > 0) continue;
        meshes_.insert(static_cast<int>(m));
        const bool forward = ba == body;
        const int from_gear = forward ? ga : gb, to_gear = forward ? gb : ga;
        const int to = forward ? bb : ba;
        const double ratio =
            static_cast<double>(spec_.gears[static_cast<size_t>(from_gear)].gear.teeth) /
            spec_.gears[static_cast<size_t>(to_gear)].gear.teeth;
        const double speed = -t_.bodies[static_cast<size_t>(body)].speed * ratio;
        if (!Reached(to)) {
          TrainBody& target = t_.bodies[static_cast<size_t>(to)];
          t_.parent_mesh[static_cast<size_t>(to)] = static_cast<int>(m);
          target.speed = speed;
          target.speed_ratio = -t_.bodies[static_cast<size_t>(body)].speed_ratio * ratio;
          queue_.push_back(to);
        } else {
          t_.loop_meshes.push_back(static_cast<int>(m));
          claims_.push_back({static_cast<int>(m), to, speed});
        }
      }
    }
  }

  // Reaches one shaft through a coupling whose other shaft is reached (ratio +1; a shaft's body is
  // its index) and queues it; false when there is none.
  bool Coupling() {
    for (size_t c = 0; c < spec_.couplings.size(); ++c) {
      const int ba = spec_.ShaftIndex(spec_.couplings[c].shaft_a);
      const int bb = spec_.ShaftIndex(spec_.couplings[c].shaft_b);
      if (couplings_.count(static_cast<int>(c)) > 0 || Reached(ba) == Reached(bb)) continue;
      couplings_.insert(static_cast<int>(c));
      const int from = Reached(ba) ? ba : bb, to = Reached(ba) ? bb : ba;
      t_.parent_mesh[static_cast<size_t>(to)] = -1;
      t_.parent_coupling[static_cast<size_t>(to)] = static_cast<int>(c);
      t_.bodies[static_cast<size_t>(to)].speed = t_.bodies[static_cast<size_t>(from)].speed;
      t_.bodies[static_cast<size_t>(to)].speed_ratio =
          t_.bodies[static_cast<size_t>(from)].speed_ratio;
      queue_.push_back(to);
      return true;
    }
    return false;
  }

  const TrainSpec& spec_;
  TrainTopology& t_;
  std::deque<int> queue_;
  std::set<int> meshes_, couplings_;
  std::vector<SpeedClaim> claims_;
};

// A coupling that closes a loop (in parallel with a gear path or other couplings) would hold a
// preload the file does not give: its zero twist at the nominal angles, the gears' at the middle of
// their backlash. Refused (after the speeds, so that a coupling between shafts at different speeds
// is told that instead).
void RequireNoCouplingInLoop(const TrainSpec& spec, const std::vector<int>& loop_couplings) {
  if (loop_couplings.empty()) return;
  const TrainCoupling& c = spec.couplings[static_cast<size_t>(loop_couplings.front())];
  throw InputError("couplings." + c.name + ".between", 0, "[" + c.shaft_a + ", " + c.shaft_b + "]",
                   "closes a loop: '" + c.shaft_b + "' is reached from '" + c.shaft_a +
                       "' by another path of meshes or couplings as well. A coupling in parallel "
                       "is statically indeterminate (its preload at assembly is not in the file) "
                       "and is not supported: join each shaft by one path");
}

}  // namespace

int TrainTopology::ParentBody(const TrainSpec& spec, int body) const {
  const int m = parent_mesh[static_cast<size_t>(body)];
  if (m >= 0) {
    const TrainMesh& mesh = spec.meshes[static_cast<size_t>(m)];
    const int a = gear_body[static_cast<size_t>(spec.GearIndex(mesh.gear_a))];
    return a == body ? gear_body[static_cast<size_t>(spec.GearIndex(mesh.gear_b))] : a;
  }
  const int c = parent_coupling[static_cast<size_t>(body)];
  if (c < 0) return -1;
  const TrainCoupling& coupling = spec.couplings[static_cast<size_t>(c)];
  const int a = spec.ShaftIndex(coupling.shaft_a);
  return a == body ? spec.ShaftIndex(coupling.shaft_b) : a;
}

double CouplingSprings::Torque(double twist) const {
  double torque = stiffness * twist;
  double below = stiffness;
  const double magnitude = std::abs(twist);
  for (const TrainCouplingStage& s : stages) {
    if (magnitude <= s.from) break;
    torque += std::copysign((s.stiffness - below) * (magnitude - s.from), twist);
    below = s.stiffness;
  }
  return torque;
}

double CouplingSprings::StaticTwist(double torque) const {
  // Walk up the stages: the twist lies in the first stage whose end carries more than |torque|.
  const double magnitude = std::abs(torque);
  double angle = 0.0, carried = 0.0, k = stiffness;
  for (const TrainCouplingStage& s : stages) {
    const double at_end = carried + k * (s.from - angle);
    if (magnitude <= at_end) break;
    angle = s.from;
    carried = at_end;
    k = s.stiffness;
  }
  return std::copysign(angle + (magnitude - carried) / k, torque);
}

double CouplingSprings::TangentStiffness(double twist) const {
  double k = stiffness;
  for (const TrainCouplingStage& s : stages) {
    if (std::abs(twist) <= s.from) break;
    k = s.stiffness;
  }
  return k;
}

int TrainSpec::GearIndex(const std::string& name) const {
  for (size_t i = 0; i < gears.size(); ++i) {
    if (gears[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

int TrainSpec::ShaftIndex(const std::string& name) const {
  for (size_t i = 0; i < shafts.size(); ++i) {
    if (shafts[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

const TrainGear* TrainSpec::FindGear(const std::string& gear) const {
  const int i = GearIndex(gear);
  return i < 0 ? nullptr : &gears[static_cast<size_t>(i)];
}

const TrainShaft* TrainSpec::FindShaft(const std::string& shaft) const {
  const int i = ShaftIndex(shaft);
  return i < 0 ? nullptr : &shafts[static_cast<size_t>(i)];
}

TrainTopology AnalyseTrainTopology(const TrainSpec& spec) {
  TrainTopology t;
  t.gear_body.assign(spec.gears.size(), -1);
  for (size_t s = 0; s < spec.shafts.size(); ++s) {
    TrainBody body;
    body.name = spec.shafts[s].name;
    body.shaft = static_cast<int>(s);
    t.bodies.push_back(body);
  }
  for (size_t g = 0; g < spec.gears.size(); ++g) {
    const TrainGear& gear = spec.gears[g];
    const int shaft = spec.ShaftIndex(gear.shaft);
    if (gear.mounting == Mounting::kFixed) {
      t.gear_body[g] = shaft;
      t.bodies[static_cast<size_t>(shaft)].gears.push_back(static_cast<int>(g));
    } else {
      TrainBody body;
      body.name = gear.name;
      body.kind = BodyKind::kLooseGear;
      body.shaft = shaft;
      body.gears = {static_cast<int>(g)};
      t.gear_body[g] = static_cast<int>(t.bodies.size());
      t.bodies.push_back(body);
    }
  }
  t.input_body = spec.ShaftIndex(spec.operating.input_shaft);
  RequireStationaryShaftsStill(spec, t);
  t.parent_mesh.assign(t.bodies.size(), -2);  // -2: not reached
  t.parent_mesh[static_cast<size_t>(t.input_body)] = -1;
  for (size_t s = 0; s < spec.shafts.size(); ++s) {
    if (spec.shafts[s].fixed) t.parent_mesh[s] = -1;  // reached: it stands (speed 0)
  }
  t.bodies[static_cast<size_t>(t.input_body)].speed = spec.operating.speed;
  t.bodies[static_cast<size_t>(t.input_body)].speed_ratio = 1.0;
  t.parent_coupling.assign(t.bodies.size(), -1);
  SpeedSearch search(spec, t);
  search.Run();
  const std::vector<int> loop_couplings = search.LoopCouplings();
  const std::vector<SpeedClaim>& loop_claims = search.claims();
  RequireConsistentLoops(spec, t, loop_claims);
  RequireNoCouplingInLoop(spec, loop_couplings);
  for (size_t b = 0; b < t.bodies.size(); ++b) {
    if (t.parent_mesh[b] != -2) continue;
    const TrainBody& body = t.bodies[b];
    const std::string path =
        body.kind == BodyKind::kShaft ? "shafts." + body.name : "gears." + body.name;
    throw InputError(path, 0, "",
                     body.kind == BodyKind::kShaft
                         ? "has no way to turn: no chain of meshes, fixed gears and couplings "
                           "connects it to the input shaft '" +
                               spec.operating.input_shaft + "'"
                         : "has no way to turn: no chain of meshes connects this loose gear to "
                           "the input shaft '" +
                               spec.operating.input_shaft + "'");
  }
  return t;
}

GearboxSpec MeshGearbox(const TrainSpec& spec, const TrainTopology& topology, int m,
                        double transmitted_torque) {
  const TrainMesh& mesh = spec.meshes[static_cast<size_t>(m)];
  const int ga = spec.GearIndex(mesh.gear_a), gb = spec.GearIndex(mesh.gear_b);
  const TrainGear& a = spec.gears[static_cast<size_t>(ga)];
  const TrainGear& b = spec.gears[static_cast<size_t>(gb)];
  GearboxSpec g;
  g.name = spec.name + " " + mesh.Name();
  g.materials = spec.materials;
  g.pinion = a.gear;
  g.wheel = b.gear;
  g.mesh = mesh.mesh;
  for (auto [gear, shaft] : {std::pair{&a, &g.input_shaft}, std::pair{&b, &g.output_shaft}}) {
    const TrainShaft& s = *spec.FindShaft(gear->shaft);
    if (s.elastic) {
      *shaft = *s.elastic;
      (*shaft)->gear_at = gear->at.value_or(0.0);
    }
  }
  g.operating.speed = std::abs(
      topology.bodies[static_cast<size_t>(topology.gear_body[static_cast<size_t>(ga)])].speed);
  g.operating.torque = transmitted_torque;
  g.analysis = spec.analysis;
  return g;
}

TrainSpec TrainOf(const GearboxSpec& spec) {
  TrainSpec t;
  t.name = spec.name;
  t.materials = spec.materials;
  for (auto [name, gear, shaft] : {std::tuple{"input", &spec.pinion, &spec.input_shaft},
                                   std::tuple{"output", &spec.wheel, &spec.output_shaft}}) {
    TrainShaft s;
    s.name = name;
    if (*shaft) {
      s.elastic = **shaft;
    } else {
      s.inertia = 0.0;  // the gear body alone turns (schema 1: rigid shaft, no inertia of its own)
    }
    t.shafts.push_back(s);
    TrainGear g;
    g.name = gear == &spec.pinion ? "pinion" : "wheel";
    g.shaft = name;
    if (*shaft) g.at = (*shaft)->gear_at;
    g.gear = *gear;
    t.gears.push_back(g);
  }
  t.meshes.push_back({"pinion", "wheel", spec.mesh, 0.0, MeshEffectiveMass::kGears});
  t.operating.input_shaft = "input";
  t.operating.speed = spec.operating.speed;
  t.operating.speed_unit = spec.operating.speed_unit;
  // The output resists the wheel's torque (a pinion torque times z2 / z1), in the file's unit.
  TrainLoad load{"output", spec.WheelTorque(), spec.operating.torque_unit};
  if (spec.operating.torque_on == TorqueOn::kPinion) load.pinion_torque = spec.operating.torque;
  t.operating.loads.push_back(load);
  t.operating.excitation = spec.operating.excitation;
  t.analysis = spec.analysis;
  return t;
}

bool IsSchemaOnePair(const TrainSpec& spec) {
  if (spec.shafts.size() != 2 || spec.gears.size() != 2 || spec.meshes.size() != 1 ||
      spec.operating.loads.size() != 1) {
    return false;
  }
  // A schema-1 shaft is rigid with no inertia of its own, or elastic with the gear at gear_at.
  const auto schema_one_body = [](const TrainShaft& s, const TrainGear& g, const char* shaft,
                                  const char* gear) {
    const bool shaft_form =
        s.elastic ? !s.inertia && g.at && *g.at == s.elastic->gear_at : s.inertia == 0.0 && !g.at;
    return s.name == shaft && g.name == gear && g.shaft == shaft &&
           g.mounting == Mounting::kFixed && s.bearings.empty() && shaft_form;
  };
  const TrainMesh& mesh = spec.meshes.front();
  const TrainLoad& load = spec.operating.loads.front();
  // A pinion torque and the output's load agree (GearboxSpec::WheelTorque).
  const bool load_form =
      !load.pinion_torque || load.torque == *load.pinion_torque *
                                                static_cast<double>(spec.gears[1].gear.teeth) /
                                                spec.gears[0].gear.teeth;
  return load_form && schema_one_body(spec.shafts[0], spec.gears[0], "input", "pinion") &&
         schema_one_body(spec.shafts[1], spec.gears[1], "output", "wheel") &&
         mesh.gear_a == "pinion" && mesh.gear_b == "wheel" && mesh.center_line_angle == 0.0 &&
         mesh.effective_mass == MeshEffectiveMass::kGears &&
         spec.operating.input_shaft == "input" && load.on == "output" && spec.couplings.empty() &&
         std::all_of(spec.operating.excitation.begin(), spec.operating.excitation.end(),
                     [](const ExcitationOrder& e) {
                       return e.kind == ExcitationKind::kAcceleration && e.on.empty();
                     });
}

GearboxSpec GearboxOf(const TrainSpec& spec) {
  if (!IsSchemaOnePair(spec)) {
    throw std::invalid_argument("GearboxOf: '" + spec.name + "' is not a train TrainOf gives");
  }
  GearboxSpec g;
  g.name = spec.name;
  g.materials = spec.materials;
  g.pinion = spec.gears[0].gear;
  g.wheel = spec.gears[1].gear;
  g.mesh = spec.meshes.front().mesh;
  g.input_shaft = spec.shafts[0].elastic;
  g.output_shaft = spec.shafts[1].elastic;
  const TrainLoad& load = spec.operating.loads.front();
  g.operating.speed = spec.operating.speed;
  g.operating.speed_unit = spec.operating.speed_unit;
  g.operating.torque = load.pinion_torque.value_or(load.torque);
  g.operating.torque_on = load.pinion_torque ? TorqueOn::kPinion : TorqueOn::kWheel;
  g.operating.torque_unit = load.torque_unit;
  g.operating.excitation = spec.operating.excitation;
  g.analysis = spec.analysis;
  return g;
}

void ValidateTrainSpec(const TrainSpec& spec) {
  if (spec.name.empty()) throw InputError("name", 0, "\"\"", "must not be empty");
  if (spec.shafts.empty()) throw InputError("shafts", 0, "{}", "needs at least one shaft");
  if (spec.gears.size() < 2) {
    throw InputError("gears", 0, Count(spec.gears.size(), "gear", "gears"),
                     "needs at least two gears");
  }
  if (spec.meshes.empty()) throw InputError("meshes", 0, "[]", "needs at least one mesh");
  RequireTrainSize(spec);
  RequireUniqueBodyNames(spec);
  for (const TrainShaft& s : spec.shafts) {
    const std::string p = "shafts." + s.name;
    if (s.inertia && !(*s.inertia >= 0.0 && std::isfinite(*s.inertia))) {
      throw InputError(p + ".inertia", 0, MessageNumber(*s.inertia), "must be >= 0");
    }
    if (s.inertia) RequireInertiaWithinLimit(p + ".inertia", *s.inertia);
    if (!s.inertia && !s.elastic) {
      throw InputError(p, 0, "", "needs inertia (a rigid shaft) or segments (an elastic shaft)");
    }
    const bool carries_gear = std::any_of(
        spec.gears.begin(), spec.gears.end(),
        [&](const TrainGear& g) { return g.shaft == s.name && g.mounting == Mounting::kFixed; });
    const bool coupled =
        std::any_of(spec.couplings.begin(), spec.couplings.end(), [&](const TrainCoupling& c) {
          return c.shaft_a == s.name || c.shaft_b == s.name;
        });
    if ((s.fixed || coupled) && s.inertia && *s.inertia == 0.0 && !carries_gear) {
      throw InputError(p + ".inertia", 0, "0",
                       std::string("must be > 0 on a ") + (s.fixed ? "fixed" : "coupled") +
                           " shaft that carries no fixed gear (the shaft alone is its body)");
    }
  }
  RequireValidCouplings(spec);
  std::vector<int> meshes_of_gear(spec.gears.size(), 0);
  for (const TrainGear& g : spec.gears) {
    const std::string p = "gears." + g.name;
    const TrainShaft* shaft = spec.FindShaft(g.shaft);
    if (shaft == nullptr) {
      throw InputError(p + ".shaft", 0, "'" + g.shaft + "'", "must name a key of shafts");
    }
    if (shaft->elastic && !g.at) {
      throw InputError(p + ".at", 0, "", "required: the gear sits on an elastic shaft");
    }
    // Each gear's own scale before the rules comparing meshing gears, so that those blame the
    // implausible gear (a module written without its unit) rather than its mate.
    ValidateGearAlone(g.gear, p);
  }
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    const TrainMesh& mesh = spec.meshes[m];
    const std::string p = MeshPath(static_cast<int>(m)) + ".gears";
    for (const std::string& name : {mesh.gear_a, mesh.gear_b}) {
      if (spec.FindGear(name) == nullptr) {
        throw InputError(p, 0, "'" + name + "'", "must name a key of gears");
      }
    }
    const TrainGear& a = *spec.FindGear(mesh.gear_a);
    const TrainGear& b = *spec.FindGear(mesh.gear_b);
    if (a.name == b.name) throw InputError(p, 0, "'" + a.name + "' twice", "needs two gears");
    if (a.shaft == b.shaft) {
      throw InputError(p, 0, "[" + a.name + ", " + b.name + "]",
                       "the two gears sit on the same shaft '" + a.shaft + "' and cannot mesh");
    }
    if (a.gear.helix_angle != b.gear.helix_angle) {
      throw InputError("gears." + b.name + ".helix_angle", 0,
                       {"{}", {InputError::Angle(b.gear.helix_angle)}},
                       {"must equal the helix angle of '" + a.name +
                            "' ({}), the gear it meshes with in " + MeshPath(static_cast<int>(m)),
                        {InputError::Angle(a.gear.helix_angle)}});
    }
    if (a.gear.helix_angle > 0.0 && a.gear.hand == b.gear.hand) {
      throw InputError("gears." + b.name + ".hand", 0,
                       b.gear.hand == Hand::kRight ? "right" : "left",
                       "must be the opposite of the hand of '" + a.name +
                           "' (an external helical pair, " + MeshPath(static_cast<int>(m)) + ")");
    }
    // A pair meshes once: a second mesh of it would double its stiffness under the same name.
    for (size_t earlier = 0; earlier < m; ++earlier) {
      const TrainMesh& e = spec.meshes[earlier];
      if ((e.gear_a == a.name && e.gear_b == b.name) ||
          (e.gear_a == b.name && e.gear_b == a.name)) {
        throw InputError(p, 0, "[" + mesh.gear_a + ", " + mesh.gear_b + "]",
                         "meshes the same pair of gears as " + MeshPath(static_cast<int>(earlier)) +
                             " ([" + e.gear_a + ", " + e.gear_b +
                             "]): a pair meshes once (a second mesh would double its stiffness)");
      }
      // Outputs name a mesh by its gears joined with '-' (CSV columns, tables, order lines).
      if (e.Name() == mesh.Name()) {
        throw InputError(p, 0, "[" + mesh.gear_a + ", " + mesh.gear_b + "]",
                         "gives the mesh name '" + mesh.Name() + "', as " +
                             MeshPath(static_cast<int>(earlier)) + " ([" + e.gear_a + ", " +
                             e.gear_b +
                             "]) does: a mesh is named by its gears joined with '-'; "
                             "rename a gear");
      }
    }
    ++meshes_of_gear[static_cast<size_t>(spec.GearIndex(a.name))];
    ++meshes_of_gear[static_cast<size_t>(spec.GearIndex(b.name))];
  }
  RequireMeshesPerGear(spec);
  for (size_t g = 0; g < spec.gears.size(); ++g) {
    if (spec.gears[g].mounting == Mounting::kLoose && meshes_of_gear[g] == 0) {
      throw InputError("gears." + spec.gears[g].name + ".mounting", 0, "loose",
                       "a loose gear needs a mesh: nothing else turns it");
    }
  }
  if (spec.FindShaft(spec.operating.input_shaft) == nullptr) {
    throw InputError("operating.speed.shaft", 0, "'" + spec.operating.input_shaft + "'",
                     "must name a key of shafts");
  }
  if (!(spec.operating.speed > 0.0 && std::isfinite(spec.operating.speed))) {
    throw InputError("operating.speed.value", 0, MessageNumber(spec.operating.speed) + " rad/s",
                     "must be > 0: the input shaft's mean speed (it turns the way it is driven)");
  }
  RequireExcitationShafts(spec);
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    const TrainLoad& load = spec.operating.loads[i];
    const std::string p = "operating.loads[" + std::to_string(i) + "]";
    if (spec.FindShaft(load.on) == nullptr && spec.FindGear(load.on) == nullptr) {
      throw InputError(p + ".on", 0, "'" + load.on + "'", "must name a shaft or a gear");
    }
    if (!(load.torque >= 0.0 && std::isfinite(load.torque))) {
      throw InputError(p + ".torque", 0, MessageNumber(load.torque), "must be >= 0");
    }
    if (!(load.viscous >= 0.0 && load.viscous <= GearboxLimits::kMaxViscousDrag)) {
      throw InputError(p + ".viscous", 0, MessageNumber(load.viscous) + " N m s/rad",
                       "must be in [0, " + MessageNumber(GearboxLimits::kMaxViscousDrag) +
                           "] N m s/rad (churning and bearing drag of large gears is 1-10)");
    }
    if (!load.relative_to.empty()) {
      const TrainShaft* carrier = spec.FindShaft(load.relative_to);
      if (carrier == nullptr) {
        std::string shafts;
        for (const TrainShaft& shaft : spec.shafts)
          shafts += (shafts.empty() ? "" : ", ") + shaft.name;
        throw InputError(p + ".relative_to", 0, "'" + load.relative_to + "'",
                         "must name a shaft, the one the drag acts relative to (the file's "
                         "shafts: " +
                             shafts + ")");
      }
      const TrainGear* on_gear = spec.FindGear(load.on);
      const std::string own_shaft = on_gear == nullptr                      ? load.on
                                    : on_gear->mounting == Mounting::kFixed ? on_gear->shaft
                                                                            : "";
      if (own_shaft == carrier->name) {
        throw InputError(
            p + ".relative_to", 0, "'" + load.relative_to + "'",
            "is the body '" + load.on + "' turns with: a drag relative to itself does nothing");
      }
    }
    const TrainGear* gear = spec.FindGear(load.on);
    const TrainShaft* shaft = gear && gear->mounting == Mounting::kFixed
                                  ? spec.FindShaft(gear->shaft)
                                  : spec.FindShaft(load.on);
    if (shaft && shaft->fixed) {
      throw InputError(p + ".on", 0, "'" + load.on + "'",
                       "is on the fixed shaft '" + shaft->name + "' (shafts." + shaft->name +
                           ".fixed: true), which does not turn: a load there does no work "
                           "(a loose gear's drag goes on the loose gear)");
    }
  }
  const TrainTopology topology = AnalyseTrainTopology(spec);
  for (size_t i = 0; i < spec.operating.loads.size(); ++i) {
    const TrainLoad& load = spec.operating.loads[i];
    if (load.torque > 0.0 && ActionOfLoad(spec, topology, i).relative_speed == 0.0) {
      throw InputError("operating.loads[" + std::to_string(i) + "].torque", 0,
                       MessageNumber(load.torque) + " N m",
                       "must be 0: '" + load.on + "' turns with '" + load.relative_to +
                           "' at the same nominal speed, so a constant drag between them has no "
                           "direction (a viscous drag may act)");
    }
  }
  // Every mesh as the schema-1 gearbox of its gears: the gear, mesh, shaft, excitation-order and
  // analysis rules of schema 1, with the train's paths in the messages. The operating limits
  // (speed, load, excitation amplitude) are the train's, on its input shaft and loads.
  for (size_t m = 0; m < spec.meshes.size(); ++m) {
    GearboxSpec pair = MeshGearbox(spec, topology, static_cast<int>(m), 0.0);
    pair.operating.excitation = spec.operating.excitation;
    try {
      ValidateGearboxSpec(pair, OperatingLimits::kLeftToTheTrain);
    } catch (const InputError& e) {
      throw e.Renamed(
          [&](const std::string& path) { return TrainPath(path, spec, static_cast<int>(m)); },
          [&](const std::string& rule) { return TrainRule(rule, spec, static_cast<int>(m)); });
    }
  }
  RequireSharedCenterDistances(spec, topology);
  ValidateTrainLimits(spec, topology);
}

}  // namespace gearnvh
