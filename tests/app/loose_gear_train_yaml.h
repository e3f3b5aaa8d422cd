// An ordinary rattling 3-mesh train in YAML (schema gearnvh/2), tests/data/loose_gear_train.yaml,
// shared with the Python tests: a-b and c-d loaded, e-f with the light gear f loose on the output
// shaft under 0.2 N m of drag; it rattles from the first cycle.
#pragma once

#include <filesystem>
#include <string>

#include "support/run_command.h"

namespace gearnvh::testing {

// Read at start-up; a missing file is an empty string, which every test then fails to load.
inline const std::string kLooseGearTrainYaml =
    ReadWholeFile(std::filesystem::path(GEARNVH_TEST_DATA_DIR) / "loose_gear_train.yaml");

}  // namespace gearnvh::testing
