// Replays tests/fuzz/regressions/: inputs that once crashed, hung or produced NaN, under the
// fuzzer's contract (tests/fuzz/fuzz_contract.h): load, either schema, into a spec with finite
// models, or InputError.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "fuzz/fuzz_contract.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

namespace fs = std::filesystem;

TEST_CASE("fuzz regressions: each input loads with a finite model or is an input error",
          "[app][fuzz]") {
  size_t files = 0;
  for (const auto& e : fs::directory_iterator(GEARNVH_FUZZ_REGRESSIONS_DIR)) {
    if (e.path().extension() == ".md") continue;
    ++files;
    INFO(e.path());
    const std::string text = testing::ReadWholeFile(e.path());
    try {
      fuzz::CheckInput(text, e.path().string());
    } catch (const std::logic_error& defect) {
      FAIL(defect.what());
    }
    // An input error names the file it came from.
    try {
      config::LoadAnyGearboxFromString(text, e.path().string());
    } catch (const InputError& error) {
      CHECK(std::string(error.what()).find(e.path().filename().string()) != std::string::npos);
    }
  }
  CHECK(files >= 7);
}

}  // namespace
}  // namespace gearnvh
