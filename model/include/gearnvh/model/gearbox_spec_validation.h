// Range and consistency rules of schema gearnvh/1, applied to a GearboxSpec in SI units.
//
// Shared by the YAML loader (which adds line numbers and the value as written) and by code that
// edits a spec programmatically (speed sweeps, atlases). Throws InputError naming the schema path,
// the value (SI) and the rule; the first broken rule wins.
#pragma once

#include <optional>
#include <string>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/gearbox_spec_limits.h"

namespace gearnvh {

// The rules on one gear alone (teeth, module, pressure and helix angle ranges, face width and
// the gear's scale, RequireGearScale) at path `p` ("gears.pinion"): checked before any rule that
// compares two gears, so that a mismatch is blamed on the implausible gear.
void ValidateGearAlone(const GearSpec& gear, const std::string& p);

// `operating`: kLeftToTheTrain for a train's mesh gearbox (see OperatingLimits).
void ValidateGearboxSpec(const GearboxSpec& spec,
                         OperatingLimits operating = OperatingLimits::kChecked);

// The first rule a speed sweep or an atlas axis breaks (>= 2 points, from < to, from > 0 on a log
// scale): the part of the range and the rule; nullopt when it keeps them all. One set of rules
// for the file's ranges and the command line's axes.
enum class SweepRangePart { kFrom, kTo, kPoints };
struct SweepRangeViolation {
  SweepRangePart part;
  std::string rule;
};
std::optional<SweepRangeViolation> FirstSweepRangeViolation(const SweepRange& range);

}  // namespace gearnvh
