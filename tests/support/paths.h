// Paths the build hands to the tests: the gearnvh executable and the bundled examples. One
// definition (inline) for every test file, so that files compiled together in a unity batch do
// not each define their own.
#pragma once

#include <string>

namespace gearnvh::testing {

inline const std::string kExamples = GEARNVH_EXAMPLES_DIR;
#ifdef GEARNVH_TEST_DATA_DIR
// A train whose tier-2 run stops out of range (tests/data/strong_rattle_train.yaml).
inline const std::string kStrongRattleTrain =
    std::string(GEARNVH_TEST_DATA_DIR) + "/strong_rattle_train.yaml";
#endif
#ifdef GEARNVH_EXE
inline const std::string kExe = GEARNVH_EXE;
#endif

}  // namespace gearnvh::testing
