// The train atlas cell (nvh/train_atlas.h), the train orbit continuation
// (nvh/train_orbit_scan.h) and the regime rules they share with the pair (nvh/rattle.h).
#include "gearnvh/nvh/train_atlas.h"

#include <catch2/catch.hpp>
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/nvh/train_orbit_scan.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

TEST_CASE("regimes: the pair's rules from impacts and the exponent", "[nvh][train][atlas]") {
  CHECK(ImpactRegime(0, 0) == RattleRegime::kNoImpact);
  CHECK(ImpactRegime(3, 0) == RattleRegime::kSingleSided);
  CHECK(ImpactRegime(0, 1) == RattleRegime::kDoubleSided);  // back-flank impacts: both sides
  CHECK(ImpactRegime(2, 5) == RattleRegime::kDoubleSided);
  CHECK(std::string(RattleRegimeName(RattleRegime::kNoImpact)) == "no impact");
  CHECK(std::string(RattleRegimeName(RattleRegime::kChaotic)) == "chaotic");
  // Chaotic: lambda T_f above the threshold and lambda above three standard errors.
  CHECK(IsChaotic(0.02, 10.0, 1.0, 0.01));
  CHECK_FALSE(IsChaotic(0.005, 10.0, 1.0, 0.01));  // below the threshold
  CHECK_FALSE(IsChaotic(0.02, 10.0, 4.0, 0.01));   // within three standard errors
  // The order the train's regime takes the worst mesh by.
  CHECK(RattleRegime::kNoImpact < RattleRegime::kSingleSided);
  CHECK(RattleRegime::kSingleSided < RattleRegime::kDoubleSided);
}

TEST_CASE("a train atlas point reports an invalid variant instead of throwing",
          "[nvh][train][atlas]") {
  TrainSpec spec = testing::TwoStageTrain(1000.0, 0.0, 1000.0);
  spec.meshes[1].mesh.backlash = -1e-6;
  TrainAtlasOptions options;
  options.cycles = 8;
  options.transient_cycles = 0;
  const TrainAtlasPoint p = ComputeTrainAtlasPoint(spec, options);
  CHECK_FALSE(p.ok);
  CHECK(p.message.find("meshes[1].backlash") != std::string::npos);
}

TEST_CASE("train orbit continuation goes on past a failed point and restarts from a settled run",
          "[nvh][train][orbits]") {
  // Permanent contact (heavy load, no excitation): the orbit is the static equilibrium of the
  // linear train, found at every good point; point 1's variant cannot be built.
  TrainSpec base = testing::TwoStageTrain(1000.0, 0.0, 1000.0);
  for (TrainMesh& m : base.meshes) m.mesh.damping_ratio = 0.01;
  TrainOrbitScanOptions options;
  options.transient_cycles = 10;
  const std::vector<TrainOrbitScanPoint> points = ScanTrainPeriodicOrbits(
      3,
      [&](int i) {
        if (i == 1) throw InputError("--sweep", 0, "x", "a variant that cannot be built");
        TrainSpec spec = base;
        spec.operating.loads[0].torque = 1000.0 + 100.0 * i;
        return spec;
      },
      options);
  REQUIRE(points.size() == 3);
  CHECK(points[0].ok);
  CHECK(points[0].found());
  CHECK(points[0].start == TrainOrbitScanPoint::Start::kSettled);
  CHECK_FALSE(points[1].ok);
  CHECK(points[1].message.find("a variant that cannot be built") != std::string::npos);
  // No previous orbit after a failed point: the third restarts from the settled run.
  CHECK(points[2].found());
  CHECK(points[2].start == TrainOrbitScanPoint::Start::kSettled);
  CHECK(TrainOrbitStartText(points[2]) == "settled run + 0 periods");
  for (size_t i : {size_t{0}, size_t{2}}) {
    CHECK(points[i].orbit.stable);
    CHECK(points[i].orbit.events_per_period == 0);
    CHECK(points[i].orbit.multipliers.size() == 2 * 3 - 2);  // 3 bodies, free rotation removed
  }
}

}  // namespace
}  // namespace gearnvh
