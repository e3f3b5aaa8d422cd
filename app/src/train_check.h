// `check` of a gear train (schema gearnvh/2): per mesh its geometry and stiffness, the bodies with
// their nominal speeds and inertias, the full FE model's and every available tier's natural
// frequencies with the static compliance matrix at the meshes, the tier-1 critical input speeds
// (every crossing of an order line with a torsional mode) and the Campbell data of the analysis
// tier over the speed sweep.
#pragma once

#include <atomic>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/nvh/campbell.h"
#include "gearnvh/reduction/train_reduction.h"

namespace gearnvh::app {

struct TrainCheck {
  GearTrain train;
  TrainTorsionalModes torsional;
  TrainStructure structure;
  NaturalModes fe;                       // the full FE model, every mesh at its mean stiffness
  std::vector<TrainReducedModel> tiers;  // the available ones, in the order of kAllTiers
  std::vector<Tier> unavailable;
  Tier campbell_tier = Tier::kTier1;  // analysis.tier
  CampbellData campbell;
};

// Throws InputError when analysis.tier is not available for this train. `cancel` is polled
// between the steps (modes, reduction, Campbell; none is polled inside): RunCancelled once set.
TrainCheck BuildTrainCheck(const TrainSpec& spec, const std::atomic<bool>* cancel = nullptr);

// The JSON document `check --json` prints for a train (keys documented in docs/results.md).
nlohmann::json TrainCheckReport(const TrainSpec& spec, const TrainCheck& check);

void PrintTrainCheck(const std::string& file, const TrainSpec& spec, const TrainCheck& check);

}  // namespace gearnvh::app
