// `check` of a gear train (schema gearnvh/2): per mesh its geometry and stiffness, the bodies with
// their nominal speeds and inertias, the tier-1 torsional modes, and the critical input speeds
// where an order line of a shaft or a mesh crosses a mode (the train's Campbell diagram at tier 1,
// whose torsional modes do not depend on speed).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "gearnvh/model/gear_train.h"

namespace gearnvh::app {

// The JSON document `check --json` prints for a train (keys documented in docs/cli.md).
nlohmann::json TrainCheckReport(const TrainSpec& spec, const GearTrain& train,
                                const TrainTorsionalModes& modes);

void PrintTrainCheck(const std::string& file, const TrainSpec& spec, const GearTrain& train,
                     const TrainTorsionalModes& modes);

}  // namespace gearnvh::app
