#include "gearnvh/nvh/rattle.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <string>

namespace gearnvh {
namespace {

TEST_CASE("rattle indices of a constructed run with known impacts", "[nvh][rattle]") {
  // 10 recorded cycles; impacts: drive at 1.0 m/s and 3.0 m/s, back at 2.0 m/s; 4 ms of 10 ms free.
  SolverResult run;
  SolverSummary& s = run.summary;
  s.recorded_cycles = 10;
  s.recorded_s = 0.010;
  s.separated_s = 0.004;
  s.drive_impacts = 2;
  s.back_impacts = 1;
  s.separations = 3;
  auto ev = [](double t, ContactState from, ContactState to, double rate) {
    return EventRecord{t, from, to, rate};
  };
  run.trajectory.events = {ev(0.001, ContactState::kFree, ContactState::kDrive, 1.0),
                           ev(0.002, ContactState::kDrive, ContactState::kFree, -0.8),
                           ev(0.003, ContactState::kFree, ContactState::kBack, -2.0),
                           ev(0.004, ContactState::kBack, ContactState::kFree, 1.5),
                           ev(0.005, ContactState::kFree, ContactState::kDrive, 3.0),
                           ev(0.006, ContactState::kDrive, ContactState::kFree, -2.0)};
  // Exact statistics of the wheel acceleration a = 100 sin(w t) over whole periods of 10 ms
  // (offset 0): int a = 0, int a^2 = 100^2 T / 2.
  TrajectoryStatistics& st = run.trajectory.statistics;
  st.duration = 0.010;
  st.wheel_acceleration.has_offset = true;
  st.wheel_acceleration.square_integral = 100.0L * 100.0L * 0.010L / 2;
  SolverResult tight = run;
  tight.trajectory.statistics.wheel_acceleration.square_integral /= 16;  // a quarter of the RMS
  const double me = 0.1;
  const RattleIndices r = ComputeRattleIndices(run, me, /*cycles per excitation=*/13.5, &tight);
  // Exact arithmetic on small numbers: tolerance a few ulps.
  CHECK(r.drive_impacts_per_cycle == Approx(0.2).epsilon(1e-15));
  CHECK(r.back_impacts_per_cycle == Approx(0.1).epsilon(1e-15));
  CHECK(r.drive_impacts_per_excitation == Approx(2.7).epsilon(1e-15));
  CHECK(r.impact_velocity_rms == Approx(std::sqrt((1.0 + 4.0 + 9.0) / 3)).epsilon(1e-15));
  CHECK(r.impact_energy_per_cycle == Approx(0.5 * me * 14.0 / 10).epsilon(1e-15));
  // Per recorded second (10 ms): as a train's loose gear reports them.
  CHECK(r.drive_impacts_per_second == Approx(200.0).epsilon(1e-15));
  CHECK(r.back_impacts_per_second == Approx(100.0).epsilon(1e-15));
  CHECK(r.impact_energy_per_second == Approx(0.5 * me * 14.0 / 0.010).epsilon(1e-15));
  CHECK(r.impact_velocity_max == 3.0);
  CHECK(r.separation_fraction == Approx(0.4).epsilon(1e-15));
  CHECK(r.wheel_acceleration_rms == Approx(100.0 / std::sqrt(2.0)).epsilon(1e-12));
  CHECK(r.acceleration_ratio == Approx(4.0).epsilon(1e-12));
  CHECK(r.regime == RattleRegime::kDoubleSided);
  run.summary.back_impacts = 0;
  CHECK(ComputeRattleIndices(run, me, 0, nullptr).regime == RattleRegime::kSingleSided);
  run.summary.drive_impacts = 0;
  CHECK(ComputeRattleIndices(run, me, 0, nullptr).regime == RattleRegime::kNoImpact);
}

TEST_CASE("rattle regimes: the names results show, and back from them", "[nvh][rattle]") {
  // The names are the results' contract (docs/results.md, docs/cli.md, tests of the JSON).
  CHECK(std::string(RattleRegimeName(RattleRegime::kNoImpact)) == "no impact");
  CHECK(std::string(RattleRegimeName(RattleRegime::kSingleSided)) == "single-sided");
  CHECK(std::string(RattleRegimeName(RattleRegime::kDoubleSided)) == "double-sided");
  CHECK(std::string(RattleRegimeName(RattleRegime::kChaotic)) == "chaotic");
  for (RattleRegime r : {RattleRegime::kNoImpact, RattleRegime::kSingleSided,
                         RattleRegime::kDoubleSided, RattleRegime::kChaotic}) {
    CHECK(RattleRegimeFromName(RattleRegimeName(r)) == r);
  }
  CHECK_FALSE(RattleRegimeFromName("").has_value());
  CHECK_FALSE(RattleRegimeFromName("Chaotic").has_value());
}

}  // namespace
}  // namespace gearnvh
