// The options a command (or the Python module) runs a gear train with, checked against the file:
// the tier the train has, the cycle counts and the run-length limit, the speed axes. Each error
// names the option as the caller spells it (OptionNames).
#pragma once

#include <optional>
#include <string>

#include "gearnvh/analysis/option_names.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {

struct TrainCommandSettings {
  Tier tier = Tier::kTier1;
  EventMethod events = EventMethod::kSpectral;
};

// What the commands accept on a train: a tier the train has (`--tier` or analysis.tier; tiers 4,
// 5 and N20 need an elastic shaft); the event method is EventMethodOf(method) (kFused runs kV3
// with the train's jumps and segment-run fusion). Throws InputError naming the option or key
// otherwise.
TrainCommandSettings CheckTrainCommandOptions(const std::optional<std::string>& tier_option,
                                              const TrainSpec& spec, LadderMethod method,
                                              const OptionNames& names = {});

// `cycles` >= `min_cycles` and `transient` >= 0 (the counts a command runs), else InputError
// naming names("cycles") or names("transient").
void RequireCycleCounts(long cycles, long min_cycles, long transient,
                        const OptionNames& names = {});

// The run-length limit of the file (GearboxLimits::kMaxSimulatedSeconds of simulated time) on the
// counts a command runs when --cycles or --transient overrides analysis: `cycles` + `transient`
// cycles of the first mesh at input speed `lowest_speed` (rad/s; a sweep's lowest) must last at
// most that long. InputError naming --transient when it was given, else --cycles; nothing to check
// when neither was given (ValidateTrainSpec has checked the file's counts).
void RequireRunLengthOfOptions(const TrainSpec& spec, double lowest_speed, long cycles,
                               long transient, const std::optional<long>& cycles_option,
                               const std::optional<long>& transient_option,
                               const OptionNames& names = {});

// The lowest input speed a command runs at, rad/s: the operating speed, or the lower end of an
// axis (atlas --x/--y, orbits --sweep) that varies operating.speed. For RequireRunLengthOfOptions.
double LowestInputSpeed(const TrainSpec& spec, const std::optional<AtlasAxis>& x,
                        const std::optional<AtlasAxis>& y = std::nullopt);

// An axis a command runs (atlas --x/--y, orbits --sweep, given as `text`) that varies
// operating.speed, held at its fastest end to the pitch-line velocity limit of the fastest mesh
// (RequirePitchLineVelocity, in the unit the axis was written in): InputError naming `field`.
// `mesh` names that mesh for a pair ("the mesh"); "" names a train's ("meshes[1] (c-d)").
void RequireAxisWithinPitchLineLimit(const TrainSpec& spec, const AtlasAxis& axis,
                                     const std::string& text, const std::string& field,
                                     const std::string& mesh = "");

}  // namespace gearnvh::app
