#include "train_command_options.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/train_reduction.h"
#include "simulate_command.h"

namespace gearnvh::app {

double LowestInputSpeed(const TrainSpec& spec, const std::optional<AtlasAxis>& x,
                        const std::optional<AtlasAxis>& y) {
  double lowest = spec.operating.speed;
  bool varied = false;
  for (const std::optional<AtlasAxis>* axis : {&x, &y}) {
    if (!*axis || (*axis)->parameter != "operating.speed") continue;
    const double low = std::min((*axis)->range.from, (*axis)->range.to);
    lowest = varied ? std::min(lowest, low) : low;
    varied = true;
  }
  return lowest;
}

void RequireAxisWithinPitchLineLimit(const TrainSpec& spec, const AtlasAxis& axis,
                                     const std::string& text, const std::string& field,
                                     const std::string& mesh) {
  if (axis.parameter != "operating.speed") return;
  const FastestMesh fastest = FastestPitchLine(spec, AnalyseTrainTopology(spec));
  const double speed = std::max(std::abs(axis.range.from), std::abs(axis.range.to));
  RequirePitchLineVelocity(field, speed, config::SpeedUnitOfAxisOption(text),
                           fastest.velocity_per_speed, mesh.empty() ? fastest.name : mesh);
}

void RequireCycleCounts(long cycles, long min_cycles, long transient, const OptionNames& names) {
  if (cycles < min_cycles) {
    throw InputError(names("cycles"), 0, std::to_string(cycles),
                     "must be >= " + std::to_string(min_cycles));
  }
  if (transient < 0) {
    throw InputError(names("transient"), 0, std::to_string(transient), "must be >= 0");
  }
}

void RequireRunLengthOfOptions(const TrainSpec& spec, double lowest_speed, long cycles,
                               long transient, const std::optional<long>& cycles_option,
                               const std::optional<long>& transient_option,
                               const OptionNames& names) {
  if (!cycles_option && !transient_option) return;
  const double hz = FirstMeshFrequency(spec, AnalyseTrainTopology(spec), lowest_speed);
  const double seconds = static_cast<double>(cycles + transient) / hz;
  if (seconds <= GearboxLimits::kMaxSimulatedSeconds) return;
  const bool transient_named = transient_option.has_value();
  throw InputError(
      names(transient_named ? "transient" : "cycles"), 0,
      std::to_string(transient_named ? *transient_option : *cycles_option),
      fmt::format("makes the {} cycles of the first mesh ({}, {}, cycles + transient) last "
                  "{:.3g} s of simulated time at {} (mesh frequency {:.3g} Hz); the limit is {} "
                  "s, as for analysis.cycles + transient_cycles",
                  cycles + transient, "meshes[0]", spec.meshes.front().Name(), seconds,
                  InUnit(lowest_speed, spec.operating.speed_unit), hz,
                  GearboxLimits::kMaxSimulatedSeconds));
}

TrainCommandSettings CheckTrainCommandOptions(const std::optional<std::string>& tier_option,
                                              const TrainSpec& spec, LadderMethod method,
                                              const OptionNames& names) {
  const Tier tier = tier_option ? ParseTier(*tier_option, names("tier")) : spec.analysis.tier;
  if (tier != Tier::kTier1 &&
      !TrainTierAvailable(AssembleTrainStructure(spec, BuildGearTrain(spec)), tier)) {
    throw InputError(tier_option ? names("tier") : "analysis.tier", 0,
                     tier_option ? *tier_option : TierName(tier),
                     "tiers 4, 5, N20 simple and N20 MTA need an elastic shaft in the train");
  }
  return {tier, EventMethodOf(method)};
}

}  // namespace gearnvh::app
