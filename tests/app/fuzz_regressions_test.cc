// Replays tests/fuzz/regressions/: inputs that once crashed, hung or produced NaN. The contract of
// the fuzzer (tests/fuzz/loader_fuzzer.cc): load into a spec with a finite model, or InputError.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "config/gearbox_loader.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/input_error.h"
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
      const GearboxSpec spec = config::LoadGearboxFromString(text, e.path().string());
      const ComponentModel model = BuildComponentModel(spec);
      CHECK(std::isfinite(model.mesh_summary.mean));
      CHECK(std::isfinite(model.mesh_summary.lste_peak_to_peak));
      CHECK(model.K.coeffs().allFinite());
    } catch (const InputError& error) {
      CHECK(std::string(error.what()).find(e.path().filename().string()) != std::string::npos);
    }
  }
  CHECK(files >= 7);
}

}  // namespace
}  // namespace gearnvh
