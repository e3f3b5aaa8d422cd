// Rules on a train's size, names and layout (ValidateTrainSpec, train_spec.cc; implemented in
// train_limits.cc). Each throws InputError naming the path, the value and the rule.
#pragma once

#include "gearnvh/model/train_spec.h"

namespace gearnvh {

// At most GearboxLimits::kMaxTrainShafts shafts, kMaxTrainGears gears and kMaxTrainMeshes meshes:
// checked first, before any work that grows with them.
void RequireTrainSize(const TrainSpec& spec);

// A name is a shaft's or a gear's, not both: a load's `on` names either.
void RequireUniqueBodyNames(const TrainSpec& spec);

// At most GearboxLimits::kMaxMeshesPerGear meshes per gear (every mesh's gears resolved).
void RequireMeshesPerGear(const TrainSpec& spec);

// Meshes between the same two shafts at one centre distance (every mesh a valid pair).
void RequireSharedCenterDistances(const TrainSpec& spec, const TrainTopology& topology);

}  // namespace gearnvh
