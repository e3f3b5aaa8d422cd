// The rules on a train's driveline elements (train_rules.h): couplings and the shafts engine orders
// act on.
#include <string>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "train_rules.h"

namespace gearnvh {

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
    if (!(c.stiffness > 0.0 && c.stiffness <= GearboxLimits::kMaxCouplingStiffness)) {
      throw InputError(p + ".stiffness", 0, MessageNumber(c.stiffness) + " N m/rad",
                       "must be in (0, " + MessageNumber(GearboxLimits::kMaxCouplingStiffness) +
                           "] N m/rad (a clutch damper's first stage is about 20, a car's "
                           "halfshaft about 1e4)");
    }
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
