// The rules on a train's driveline elements (train_rules.h): couplings and the shafts engine orders
// act on.
#include <string>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "train_rules.h"

namespace gearnvh {

namespace {

void RequireCouplingStiffness(const std::string& path, double k) {
  if (!(k > 0.0 && k <= GearboxLimits::kMaxCouplingStiffness)) {
    throw InputError(path, 0, MessageNumber(k) + " N m/rad",
                     "must be in (0, " + MessageNumber(GearboxLimits::kMaxCouplingStiffness) +
                         "] N m/rad (a clutch damper's first stage is about 20, a car's "
                         "halfshaft about 1e4)");
  }
}

// A multi-stage coupling's stages end at rising angles in (0, kMaxCouplingStageAngle] and stiffen
// one after the other: the curve stays convex, so every stage change is a wall the twist crosses
// (a dead-band spring, docs/gear-trains.md) and the static twist is unique.
void RequireCouplingStages(const TrainCoupling& c, const std::string& p) {
  if (static_cast<int>(c.stages.size()) + 1 > GearboxLimits::kMaxCouplingStages) {
    throw InputError(p + ".stages", 0, std::to_string(c.stages.size() + 1) + " stages",
                     "must be at most " + std::to_string(GearboxLimits::kMaxCouplingStages) +
                         " (a clutch damper has two to four)");
  }
  double angle = 0.0, stiffness = c.stiffness;
  for (size_t s = 0; s < c.stages.size(); ++s) {
    const TrainCouplingStage& stage = c.stages[s];
    const std::string to = p + ".stages[" + std::to_string(s) + "].to";
    const double deg = 180.0 / 3.14159265358979323846;
    if (!(stage.from > angle && stage.from <= GearboxLimits::kMaxCouplingStageAngle)) {
      throw InputError(
          to, 0, MessageNumber(stage.from * deg) + " deg",
          "must be above " +
              (s == 0 ? std::string("0")
                      : "the stage before's end, " + MessageNumber(angle * deg) + " deg,") +
              " and at most " + MessageNumber(GearboxLimits::kMaxCouplingStageAngle * deg) +
              " deg (the stages end at rising twist angles)");
    }
    const std::string k = p + ".stages[" + std::to_string(s + 1) + "].stiffness";
    RequireCouplingStiffness(k, stage.stiffness);
    if (!(stage.stiffness > stiffness)) {
      throw InputError(k, 0, MessageNumber(stage.stiffness) + " N m/rad",
                       "must be above the stage before's " + MessageNumber(stiffness) +
                           " N m/rad: stages stiffen with the twist (a softer stage after a "
                           "stiffer one is not built)");
    }
    angle = stage.from;
    stiffness = stage.stiffness;
  }
}

}  // namespace

// Each coupling joins two distinct shafts of the file, at most once per pair, with a plausible
// stiffness and damping. (Whether they turn alike is the topology's rule.)
void RequireValidCouplings(const TrainSpec& spec) {
  for (size_t i = 0; i < spec.couplings.size(); ++i) {
    const TrainCoupling& c = spec.couplings[i];
    const std::string p = "couplings." + c.name;
    for (const std::string& name : {c.shaft_a, c.shaft_b}) {
      const TrainShaft* shaft = spec.FindShaft(name);
      const std::string value = "[" + c.shaft_a + ", " + c.shaft_b + "]";
      if (shaft != nullptr && shaft->elastic) {
        throw InputError(p + ".between", 0, value,
                         "names the elastic shaft '" + name +
                             "': a coupling joins rigid shafts (where it attaches along an "
                             "elastic shaft is not built yet; model the shaft's end as a rigid "
                             "shaft)");
      }
      if (shaft != nullptr) continue;
      if (const TrainGear* gear = spec.FindGear(name)) {
        throw InputError(p + ".between", 0, value,
                         "must name two shafts: '" + name + "' is a gear (on shaft '" +
                             gear->shaft + "'); a coupling joins shafts");
      }
      std::string shafts;
      for (const TrainShaft& s : spec.shafts) shafts += (shafts.empty() ? "" : ", ") + s.name;
      throw InputError(
          p + ".between", 0, value,
          "must name two shafts: '" + name + "' is none of the file's (" + shafts + ")");
    }
    if (c.shaft_a == c.shaft_b) {
      throw InputError(p + ".between", 0, "[" + c.shaft_a + ", " + c.shaft_b + "]",
                       "must name two different shafts");
    }
    for (size_t j = 0; j < i; ++j) {
      const TrainCoupling& e = spec.couplings[j];
      if ((e.shaft_a == c.shaft_a && e.shaft_b == c.shaft_b) ||
          (e.shaft_a == c.shaft_b && e.shaft_b == c.shaft_a)) {
        throw InputError(p + ".between", 0, "[" + c.shaft_a + ", " + c.shaft_b + "]",
                         "joins the shafts couplings." + e.name +
                             " already joins (springs in parallel: give one coupling their sum)");
      }
    }
    const std::string first = c.stages.empty() ? p + ".stiffness" : p + ".stages[0].stiffness";
    RequireCouplingStiffness(first, c.stiffness);
    RequireCouplingStages(c, p);
    if (!(c.damping >= 0.0 && c.damping <= GearboxLimits::kMaxCouplingDamping)) {
      throw InputError(
          p + ".damping", 0, MessageNumber(c.damping) + " N m s/rad",
          "must be in [0, " + MessageNumber(GearboxLimits::kMaxCouplingDamping) + "] N m s/rad");
    }
  }
}

// Each excitation order's `on` names a turning shaft of the file.
void RequireExcitationShafts(const TrainSpec& spec) {
  for (size_t i = 0; i < spec.operating.excitation.size(); ++i) {
    const std::string& on = spec.operating.excitation[i].on;
    if (on.empty()) continue;
    const std::string p = "operating.excitation[" + std::to_string(i) + "].on";
    const TrainShaft* shaft = spec.FindShaft(on);
    if (shaft == nullptr) {
      std::string shafts;
      for (const TrainShaft& s : spec.shafts) shafts += (shafts.empty() ? "" : ", ") + s.name;
      throw InputError(
          p, 0, "'" + on + "'",
          "must name a shaft (the file's shafts: " + shafts + "); an engine order acts on a shaft");
    }
    if (shaft->fixed) {
      throw InputError(p, 0, "'" + on + "'",
                       "is a fixed shaft (shafts." + on +
                           ".fixed: true), which does not turn: an order of its speed is none");
    }
  }
}

}  // namespace gearnvh
