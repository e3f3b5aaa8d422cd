// Rules on a train's size, names and layout (ValidateTrainSpec, train_spec.cc; implemented in
// train_limits.cc unless said). Each throws InputError naming the path, the value and the rule.
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

// Each coupling joins two distinct rigid shafts of the file, at most one per pair, with a plausible
// stiffness and damping (whether they turn alike, and at all, is the topology's rule;
// train_driveline_rules.cc).
void RequireValidCouplings(const TrainSpec& spec);

// Each excitation order's `on` names a turning shaft of the file (train_driveline_rules.cc).
void RequireExcitationShafts(const TrainSpec& spec);

}  // namespace gearnvh
