// Constant-contact cycle maps and certified jumps on gear trains (solver/train_cycle_map.h,
// TrainStepperOptions::jumps): a jumped transient equals the stepped one and the linear periodic
// steady state; a rattling train is never certified; a long common period is refused; no
// allocation.
#include "gearnvh/solver/train_cycle_map.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"
#include "support/allocation_counter.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;
using Jumps = TrainStepperSummary::Jumps;

// Large load, small engine order: every mesh stays in drive contact (a loaded two-stage reducer).
Model Loaded() { return Model(testing::TwoStageTrain(300.0, 100.0, 300.0)); }

using Run = testing::RecordedTrainRun;
using testing::RunTrainFromStatic;

TEST_CASE("train jumps: a loaded two-stage reducer jumped equals it stepped", "[solver][train]") {
  const Model s = Loaded();
  const TrainTables& t = s.tables;
  REQUIRE(t.common_period > 0.0);
  const double start = 20.0 * t.common_period, end = start + 2.0 * t.common_period;
  const Run stepped = RunTrainFromStatic(t, false, start, end);
  const Run jumped = RunTrainFromStatic(t, true, start, end);
  CHECK(stepped.summary.jumps == Jumps::kDisabled);
  CHECK(stepped.summary.events == 0);
  REQUIRE(jumped.summary.jumps == Jumps::kJumped);
  // One period is stepped before the first certificate (it needs a whole period without a switch).
  CHECK(jumped.summary.jumped_periods >= 18);
  CHECK(jumped.summary.events == 0);
  CHECK(jumped.summary.cycle_map_builds == 1);
  CHECK(std::abs(jumped.summary.jumped_time - static_cast<double>(jumped.summary.jumped_periods) *
                                                  t.common_period) <= 1e-12 * start);
  CHECK(jumped.summary.grid_segments < stepped.summary.grid_segments / 5);
  // Tolerance: the stepped run reaches the periodic orbit through 20 periods of closed-form pieces
  // (state error ~ cond(S) eps per piece, damped), the jumped one through the Pade-built period
  // map's fixed point; both are the same orbit to rounding (the transient, ~e^(-zeta w t) over
  // 4 s, is far below it). Measured 3e-13 to 3e-12 of the TE p-p (p-p ~ 0.65 of the mean TE
  // here); 1e-10 leaves 30x for other compilers' rounding and is far below any modelling
  // difference (a wrong segment input or stiffness moves the p-p by > 1e-4).
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    const TrainMeshStatistics& a = stepped.stats.meshes[i];
    const TrainMeshStatistics& b = jumped.stats.meshes[i];
    const double pp = a.te_peak_to_peak;
    INFO("mesh " << i << ": TE mean " << a.te_mean << " / " << b.te_mean << ", p-p " << pp << " / "
                 << b.te_peak_to_peak << ", RMS " << a.te_rms << " / " << b.te_rms);
    CHECK(pp > 0.0);
    CHECK(std::abs(a.te_mean - b.te_mean) <= 1e-10 * pp);
    CHECK(std::abs(a.te_rms - b.te_rms) <= 1e-10 * pp);
    CHECK(std::abs(a.te_peak_to_peak - b.te_peak_to_peak) <= 1e-10 * pp);
    CHECK(std::abs(a.force_max - b.force_max) <= 1e-10 * a.force_max);
    const double te_a = t.meshes[i].v.dot(stepped.state.head(t.n));
    const double te_b = t.meshes[i].v.dot(jumped.state.head(t.n));
    CHECK(std::abs(te_a - te_b) <= 1e-10 * pp);
  }
  // Velocities, the free rotation's included (the engine order swings it, no mean torque drives
  // it): measured 2.4e-10 of their norm, the rounding the stepped run sums over ~10^4 pieces into
  // the neutral rigid velocity (nothing damps it); 1e-8 bounds that.
  const Eigen::VectorXd va = stepped.state.segment(t.n, t.n), vb = jumped.state.segment(t.n, t.n);
  CHECK((va - vb).norm() <= 1e-8 * va.norm());
}

TEST_CASE("train jumps: the jumped state is the linear periodic steady state", "[solver][train]") {
  // Reference: the period map assembled in the test from dense Pade propagators of an independent
  // assembly (train_reference.h), input held per grid segment, and its fixed point by a
  // complete-orthogonal solve of (I - P) y = p on the full elastic block (not the quotient the
  // cycle map uses): the free rotation's position is its one null direction and moves no TE.
  const Model s = Loaded();
  const TrainTables& t = s.tables;
  const int n = t.n;
  const Eigen::VectorXd y = testing::DriveContactPeriodicState(t).z;

  const auto [z0, states0] = TrainStaticState(t);
  TrainStepper stepper(t, {}, z0, states0);
  const double horizon = 30.0 * t.common_period;
  REQUIRE(stepper.Run(horizon));
  REQUIRE(stepper.summary().jumps == Jumps::kJumped);
  // Without a recorder the jump goes as far as end_time; it stops at a period start.
  CHECK(std::abs(stepper.time() - horizon) <= 1e-12 * horizon);
  // Tolerance as the permanent-contact test of train_stepper_test.cc: the same model through two
  // propagations of ~500 grid segments; 1e-11 of the TE is above their rounding (~1e-13) and far
  // below a modelling difference. Here the jump lands on the orbit itself (the transient's factor
  // rho(Pq)^28 is negligible), so the comparison is at a period start.
  for (const TrainMeshTable& mt : t.meshes) {
    const double expected = mt.v.dot(y.head(n));
    const double got = mt.v.dot(stepper.state().head(n));
    INFO("TE " << got << " m against " << expected << " m");
    CHECK(std::abs(got - expected) <= 1e-11 * std::abs(expected));
    const double rate = mt.v.dot(y.segment(n, n));
    INFO("TE rate " << mt.v.dot(stepper.state().segment(n, n)) << " m/s against " << rate);
    // Measured 2.6e-12 of the rate: the rate is the TE's difference quotient at the mesh
    // frequency, so its relative rounding is a little above the TE's.
    CHECK(std::abs(mt.v.dot(stepper.state().segment(n, n)) - rate) <= 1e-10 * std::abs(rate));
  }
}

// Samples every mesh's drive gap g = v_j x - Wall along `periods` common periods from z (at a
// period start), `per_segment` points per grid segment, on dense Pade propagators of the
// independent assembly (train_reference.h), the inputs (excitation and error means) held per grid
// segment as the map holds them.
// Returns, per mesh, the gaps at every sample.
std::vector<std::vector<double>> SampleGaps(const TrainTables& t,
                                            const std::vector<ContactState>& states,
                                            Eigen::VectorXd z, int periods, int per_segment) {
  const int n = t.n;
  std::vector<std::vector<double>> gaps(t.meshes.size());
  const double until = periods * t.common_period * (1.0 - 1e-12);
  for (TrainGrid grid(t); grid.start() < until; grid.Next()) {
    const double h = grid.end() - grid.start();
    t.SetInputs(grid.cycles(), grid.segments(), grid.start(), h, z);
    const Eigen::MatrixXd A = AssembleTrainGenerator(t, grid.segments(), states);
    const double w_ref = ReferenceFrequency(A, n);
    const Eigen::MatrixXd step = BalancedExpm(A, h / per_segment, n, w_ref);
    for (int k = 0; k <= per_segment; ++k) {
      for (size_t j = 0; j < t.meshes.size(); ++j) {
        const int segment = grid.segments()[j];
        gaps[j].push_back(t.meshes[j].v.dot(z.head(n)) -
                          t.Wall(static_cast<int>(j), segment, true, z));
      }
      if (k < per_segment) z = (step * z).eval();
    }
  }
  return gaps;
}

TEST_CASE("train jumps: the certificate's margins and bounds hold along the orbit and a transient",
          "[solver][train]") {
  const Model s = Loaded();
  const TrainTables& t = s.tables;
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  long segments = 0;
  for (TrainGrid grid(t); grid.start() < t.common_period * (1.0 - 1e-12); grid.Next()) ++segments;
  CHECK(CountCommonPeriodSegments(t, 1L << 40) == segments);
  TrainCycleMap map(t, drive, 0.01, segments);
  REQUIRE(map.info() == TrainCycleMap::Info::kSuccess);

  // The margin M_j is a lower bound of the orbit's gap over the period (chords between nodes,
  // the curvature and the Taylor tail subtracted) and a tight one: sampled at 128 points per grid
  // segment (the fastest mode turns ~2 rad per grid segment here, so the samples miss the true
  // minimum by < 1e-4 of its amplitude; 16 points missed 8 %), the margin is below the sampled
  // minimum and within 2 % of it (measured 0.4 % on mesh 0, whose margin is smallest).
  const std::vector<std::vector<double>> orbit = SampleGaps(t, drive, map.orbit(), 1, 128);
  for (size_t j = 0; j < t.meshes.size(); ++j) {
    const double sampled = *std::min_element(orbit[j].begin(), orbit[j].end());
    INFO("mesh " << j << ": margin " << map.margins()[static_cast<Eigen::Index>(j)]
                 << " m, sampled minimum " << sampled << " m");
    CHECK(map.margins()[static_cast<Eigen::Index>(j)] <= sampled);
    CHECK(map.margins()[static_cast<Eigen::Index>(j)] >= 0.98 * sampled);
  }

  // A transient: the orbit's elastic coordinates scaled by 1 +- 2e-3. Certify's bound B_j
  // (sum over modes of |a_i| times the mode's largest gap) holds at every sample of the next three
  // periods, |g_j(z) - g_j(orbit)| <= B_j, since it bounds every future period (measured: the
  // deviation is 13 % of the bound on both meshes; the bound adds the modes' moduli).
  Eigen::VectorXd z = map.orbit();
  const int n = t.n;
  for (int i = 0; i < 2 * n; ++i) z[i] *= 1.0 + 2e-3 * std::sin(1.0 + i);
  const bool certified = map.Certify(z);
  INFO("bounds " << map.deviation_bounds().transpose() << " m, margins "
                 << map.margins().transpose() << " m");
  REQUIRE(certified);
  const std::vector<std::vector<double>> moved = SampleGaps(t, drive, z, 3, 4);
  const std::vector<std::vector<double>> rest = SampleGaps(t, drive, map.orbit(), 3, 4);
  for (size_t j = 0; j < t.meshes.size(); ++j) {
    double deviation = 0.0;
    for (size_t k = 0; k < moved[j].size(); ++k)
      deviation = std::max(deviation, std::abs(moved[j][k] - rest[j][k]));
    const double bound = map.deviation_bounds()[static_cast<Eigen::Index>(j)];
    INFO("mesh " << j << ": deviation " << deviation << " m, bound " << bound << " m");
    CHECK(deviation > 0.0);
    CHECK(deviation <= bound);
  }
}

TEST_CASE("train jumps: a rattling train is never certified", "[solver][train]") {
  const Model s(testing::RattlerTrain(1500.0));
  const TrainTables& t = s.tables;
  REQUIRE(t.common_period > 0.0);
  const double end = 12.0 * t.common_period;
  const Run jumped = RunTrainFromStatic(t, true, end, end);
  const Run stepped = RunTrainFromStatic(t, false, end, end);
  CHECK(jumped.summary.events > 10);
  CHECK(jumped.summary.jumped_periods == 0);
  CHECK(jumped.summary.jumps != Jumps::kJumped);
  CHECK((jumped.summary.jumps == Jumps::kNoConstantContact ||
         jumped.summary.jumps == Jumps::kNotCertified ||
         jumped.summary.jumps == Jumps::kMapRefused));
  // No jump: the same computation, bit for bit.
  CHECK(jumped.state == stepped.state);
}

TEST_CASE("train jumps: a common period longer than the limit is not mapped", "[solver][train]") {
  const Model s = Loaded();
  const TrainTables& t = s.tables;
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.max_cycle_map_segments = 100;  // the period has ~500 grid segments
  TrainStepper stepper(t, options, z0, states0);
  REQUIRE(stepper.Run(12.0 * t.common_period));
  const TrainStepperSummary summary = stepper.summary();
  CHECK(summary.jumps == Jumps::kPeriodTooLong);
  CHECK(summary.jumped_periods == 0);
  CHECK(summary.cycle_map_builds == 0);
  CHECK(summary.cycle_map_segments == 101);  // counting stops past the limit
  CHECK(summary.events == 0);

  TrainStepperOptions bad;
  bad.max_cycle_map_segments = 0;
  CHECK_THROWS_WITH(bad.Validate(), Catch::Contains("max_cycle_map_segments"));
  bad = {};
  bad.min_jump_periods = 0;
  CHECK_THROWS_WITH(bad.Validate(), Catch::Contains("min_jump_periods"));
  bad = {};
  bad.jump_margin_fraction = 1.0;
  CHECK_THROWS_WITH(bad.Validate(), Catch::Contains("jump_margin_fraction"));
}

TEST_CASE("train jumps: a transient shorter than min_jump_periods is not mapped",
          "[solver][train]") {
  const Model s = Loaded();
  const TrainTables& t = s.tables;
  const double start = 5.0 * t.common_period;  // 4 periods left after the first: below 8
  const Run run = RunTrainFromStatic(t, true, start, start + t.common_period);
  CHECK(run.summary.jumps == Jumps::kTransientTooShort);
  CHECK(run.summary.cycle_map_builds == 0);
  CHECK(run.summary.jumped_periods == 0);
}

TEST_CASE("train jumps: no common period means no jump, and says so", "[solver][train]") {
  // An engine order of 1/1001 of the input speed has no common period within 1000 revolutions.
  TrainSpec spec = testing::TwoStageTrain(300.0, 100.0, 300.0);
  spec.operating.excitation = {{1.0 / 1001.0 + 2.0, 100.0, 0.0}};
  const Model s(spec);
  REQUIRE(s.tables.common_period == 0.0);
  const auto [z0, states0] = TrainStaticState(s.tables);
  TrainStepper stepper(s.tables, {}, z0, states0);
  REQUIRE(stepper.Run(0.05));
  CHECK(stepper.summary().jumps == Jumps::kNoCommonPeriod);
  CHECK(stepper.summary().cycle_map_builds == 0);
  CHECK(stepper.summary().jumped_periods == 0);
}

TEST_CASE("train jumps: a certificate and a jump do not allocate once the map is built",
          "[solver][train][allocation]") {
  const Model s = Loaded();
  const TrainTables& t = s.tables;
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepper stepper(t, {}, z0, states0);
  const double start = 12.0 * t.common_period, end = start + 0.5 * t.common_period;
  TrainRecorder warm(t, 32, start);
  REQUIRE(stepper.Run(end, &warm));  // builds the tuples and the cycle map
  REQUIRE(stepper.summary().jumps == Jumps::kJumped);
  stepper.Reset(z0, states0);
  TrainRecorder recorder(t, 32, start);
  testing::AllocationCounter counter;
  REQUIRE(stepper.Run(end, &recorder));
  CHECK(counter.count() == 0);
  CHECK(stepper.summary().jumped_periods >= 8);
  CHECK(stepper.summary().cycle_map_builds == 0);
}

}  // namespace
}  // namespace gearnvh
