// Range and consistency rules of schema gearnvh/1, applied to a GearboxSpec in SI units.
//
// Shared by the YAML loader (which adds line numbers and the value as written) and by code that
// edits a spec programmatically (speed sweeps, atlases). Throws InputError naming the schema path,
// the value (SI) and the rule; the first broken rule wins.
#pragma once

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/gearbox_spec_limits.h"

namespace gearnvh {

// `operating`: kLeftToTheTrain for a train's mesh gearbox (see OperatingLimits).
void ValidateGearboxSpec(const GearboxSpec& spec,
                         OperatingLimits operating = OperatingLimits::kChecked);

}  // namespace gearnvh
