// Warnings on a train's loads that check and simulate say (with the model's warnings): a train
// with no load at all, and one whose output shaft carries none. Either may be meant (a rattle
// study at idle), but a forgotten load changes every mesh's operating point silently.
#pragma once

#include <string>
#include <vector>

#include "gearnvh/model/train_spec.h"

namespace gearnvh {

// The output shafts are the ends of the train: the shafts other than the input that no other
// shaft is reached through (on the topology's spanning tree from the input).
std::vector<std::string> TrainLoadWarnings(const TrainSpec& spec, const TrainTopology& topology);

}  // namespace gearnvh
