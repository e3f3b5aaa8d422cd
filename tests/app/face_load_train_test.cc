// The load across the face of a train's meshes (docs/design.md §2.5) on the bundled two-stage
// reducer, whose elastic shafts tilt the gears under load.
#include <catch2/catch.hpp>
#include <numbers>
#include <utility>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gear_train.h"
#include "support/paths.h"

namespace gearnvh::app {
namespace {

// Writing the second mesh the other way round ([g4, g3], its line of centres turned by 180°)
// describes the same gearbox: its load then sits on the listed mesh's back flank, and the shafts'
// tilt must come out the same (f_sh of the loaded flank, and the first mesh's, which the second
// one's coupling in the static solve would change if that flank were coupled wrongly). The back
// flank's own stiffness stands in by the drive flank's (a documented approximation: gear-trains),
// so K_Hbeta agrees to ~1e-3 there; the tilt itself to the static solve's rounding (1e-8).
TEST_CASE("a train mesh written the other way round gets the same shaft misalignment",
          "[app][face]") {
  const TrainSpec spec =
      config::LoadAnyGearboxFile(testing::kExamples + "/two_stage_helical_reducer.yaml").train;
  TrainSpec swapped = spec;
  std::swap(swapped.meshes[1].gear_a, swapped.meshes[1].gear_b);
  swapped.meshes[1].center_line_angle += std::numbers::pi;
  const GearTrain a = BuildGearTrain(spec), b = BuildGearTrain(swapped);
  REQUIRE_FALSE(a.meshes[1].back_flank_loaded);
  REQUIRE(b.meshes[1].back_flank_loaded);
  for (size_t m = 0; m < 2; ++m) {
    const FaceLoad& x = a.meshes[m].cycle.face;
    const FaceLoad& y = b.meshes[m].cycle.face;
    INFO("mesh " << m << ": f_sh " << x.shaft_misalignment << " / " << y.shaft_misalignment);
    CHECK(x.modelled());
    CHECK(std::abs(x.shaft_misalignment) > 1e-6);  // a few µm: the check is not vacuous
    CHECK(y.shaft_misalignment == Approx(x.shaft_misalignment).epsilon(1e-8));
    CHECK(y.factor == Approx(x.factor).epsilon(m == 0 ? 1e-8 : 2e-3));
  }
}

}  // namespace
}  // namespace gearnvh::app
