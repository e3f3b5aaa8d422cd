// The validation ladder of a gear train (schema gearnvh/2, docs/design.md §8 and §11): the exact
// train solver at analysis.tier (V3) against the CVODE reference (TE and every event) and against
// its V2 and V1 event methods, over the first cycles of the run from the static state.
#pragma once

#include <vector>

#include "gearnvh/model/train_spec.h"
#include "validation_ladder.h"

namespace gearnvh::app {

std::vector<ValidationRow> RunTrainValidationLadder(const TrainSpec& spec);

}  // namespace gearnvh::app
