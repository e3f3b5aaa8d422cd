// A run whose response grows without bound stops with an out-of-range status (SolverStatus::
// kOutOfRange, TrainStepperSummary::Info::kOutOfRange) once a flank gap passes the teeth's whole
// depth beyond a wall, instead of reporting success with metre-sized TE.
//
// The case: the flexible-shaft pair at the preprint's strong-rattle point (7548 rpm, 20 N m, order
// 15.5 of 2e5 rad/s^2). At tier 2 its lateral modes are damped only by the bearings (zeta ~3e-4),
// and the model lets one flank at a time carry load: once the gears come together by more than
// b / sin(alpha), the flank that engages next starts compressed and adds energy at every switch.
// An independent integration of the same equations (scipy expm and root finding) grows at the
// same rate, ~0.08 per mesh cycle, so this is the model's solution, not a solver fault.
#include <catch2/catch.hpp>
#include <numbers>

#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "solver/solver_fixture.h"

namespace gearnvh::testing {
namespace {

GearboxSpec StrongRattle() {
  GearboxSpec s = FlexibleShaftsPair();
  s.operating.speed = 7548.387097 * std::numbers::pi / 30.0;
  s.operating.torque = 20.0;
  s.operating.excitation = {{15.5, 200000.0, 0.0}};
  return s;
}

SolverResult RunPair(const SegmentTables& tables, long cycles) {
  const auto [z0, state0] = StaticInitialState(tables);
  SolverOptions options;
  options.cycles = cycles;
  options.transient_cycles = 0;
  options.record_trajectory = false;
  return SimulateExact(tables, z0, state0, options);
}

TEST_CASE("out of range: the whole depth is r_a - r_f of the shallower gear") {
  // Standard tooth proportions: addendum 1 m, dedendum 1.25 m, so 2.25 m (1e-14: the radii are
  // sums and differences of ~5e-2 m, each rounded, against a 6.75e-3 m difference).
  const PairGeometry g = ComputePairGeometry(StandardPair(31, 47, 3e-3, 30e-3));
  CHECK(WholeDepth(g) == Approx(2.25 * 3e-3).epsilon(1e-14));
}

TEST_CASE("out of range: a pair's growing response stops at the limit, a bounded one runs on") {
  const SolverSetup unstable(StrongRattle(), Tier::kTier2);
  const double b = unstable.tables.half_backlash;
  CHECK(unstable.tables.displacement_limit == Approx(2.0 * b + 2.25 * 3e-3).epsilon(1e-14));
  const SolverResult grown = RunPair(unstable.tables, 500);
  CHECK(grown.summary.status == SolverStatus::kOutOfRange);
  CHECK(std::string(SolverStatusName(grown.summary.status)) == "out_of_range");
  CHECK(grown.summary.mesh_cycles < 500);
  CHECK_THAT(grown.summary.message, Catch::Contains("past the teeth's whole depth"));
  // Stopped at the first cycle end past the limit: the gap is beyond it, and finite.
  const SegmentSystem& s = unstable.tables.systems[0][static_cast<int>(ContactState::kFree)];
  const double gap = std::max(std::abs(s.gap_drive.dot(grown.final_state)),
                              std::abs(s.gap_back.dot(grown.final_state)));
  CHECK(gap > unstable.tables.displacement_limit);
  CHECK(std::isfinite(gap));

  // The same point at tier 1 (one line of action: both flanks cannot overlap) rattles hard and
  // stays bounded, as does tier 2 without the excitation (it stays in drive contact).
  const SolverSetup torsional(StrongRattle(), Tier::kTier1);
  const SolverResult rattled = RunPair(torsional.tables, 500);
  CHECK(rattled.summary.status == SolverStatus::kSuccess);
  CHECK(rattled.summary.events > 500);
  GearboxSpec quiet_spec = StrongRattle();
  quiet_spec.operating.excitation.clear();
  const SolverSetup quiet(quiet_spec, Tier::kTier2);
  CHECK(RunPair(quiet.tables, 500).summary.status == SolverStatus::kSuccess);
}

TEST_CASE("out of range: the limit is on the gaps themselves") {
  // The idle pair rattles across its backlash: its gaps g+ and g- = g+ + 2b (tier 1) sweep
  // [-2b, 0] and [0, 2b] up to a few um of penetration, so a limit of 1.01 b is passed within a
  // few cycles while 2.2 b never is. A check on the mesh deflection v^T x = g+ + e + b (|.| <= ~b)
  // instead would not stop at 1.01 b. The same on the pair's one-mesh train.
  SolverSetup idle(IdleRattleSpec(), Tier::kTier1);
  const double b = idle.tables.half_backlash;
  idle.tables.displacement_limit = 1.01 * b;
  const SolverResult stopped = RunPair(idle.tables, 50);
  CHECK(stopped.summary.status == SolverStatus::kOutOfRange);
  CHECK(stopped.summary.mesh_cycles < 50);
  idle.tables.displacement_limit = 2.2 * b;
  CHECK(RunPair(idle.tables, 50).summary.status == SolverStatus::kSuccess);
  idle.tables.displacement_limit = 0.0;  // no limit
  CHECK(RunPair(idle.tables, 50).summary.status == SolverStatus::kSuccess);

  const TrainSpec spec = TrainOf(IdleRattleSpec());
  TrainTables train = BuildTrainTablesAtTier(spec, BuildGearTrain(spec), Tier::kTier1);
  const auto [z0, states0] = TrainStaticState(train);
  const double period = train.meshes[0].period;
  train.meshes[0].displacement_limit = 1.01 * b;
  TrainStepper tight(train, {}, z0, states0);
  CHECK_FALSE(tight.Run(50 * period));
  CHECK(tight.summary().info == TrainStepperSummary::Info::kOutOfRange);
  train.meshes[0].displacement_limit = 2.2 * b;
  TrainStepper loose(train, {}, z0, states0);
  CHECK(loose.Run(50 * period));
  // A run shorter than the check's cadence (64 grid segments) is checked at its end: at rest in
  // drive contact the back gap is -2b, past a limit of b.
  train.meshes[0].displacement_limit = b;
  TrainStepper brief(train, {}, z0, states0);
  CHECK_FALSE(brief.Run(0.1 * period));
  CHECK(brief.summary().info == TrainStepperSummary::Info::kOutOfRange);
}

TEST_CASE("out of range: a train's growing response stops and names its mesh") {
  const TrainSpec spec = TrainOf(StrongRattle());
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables tables = BuildTrainTablesAtTier(spec, train, Tier::kTier2);
  REQUIRE(tables.meshes.size() == 1);
  CHECK(tables.meshes[0].displacement_limit ==
        Approx(2.0 * tables.meshes[0].half_backlash + 2.25 * 3e-3).epsilon(1e-14));
  const auto [z0, states0] = TrainStaticState(tables);
  TrainStepper stepper(tables, {}, z0, states0);
  const double period = tables.meshes[0].period;
  CHECK_FALSE(stepper.Run(500 * period));
  const TrainStepperSummary summary = stepper.summary();
  CHECK(summary.info == TrainStepperSummary::Info::kOutOfRange);
  CHECK(summary.stopped_from < 500 * period);
  CHECK(summary.out_of_range_gap > summary.out_of_range_limit);
  const std::string message = TrainStepperMessage(summary);
  CHECK_THAT(message, Catch::Contains("on mesh " + tables.meshes[0].name));
  CHECK_THAT(message, Catch::Contains("past the teeth's whole depth"));

  const TrainTables torsional = BuildTrainTablesAtTier(spec, train, Tier::kTier1);
  const auto [zt, st] = TrainStaticState(torsional);
  TrainStepper bounded(torsional, {}, zt, st);
  CHECK(bounded.Run(500 * period));
  CHECK(bounded.summary().info == TrainStepperSummary::Info::kSuccess);
}

}  // namespace
}  // namespace gearnvh::testing
