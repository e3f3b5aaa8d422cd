// Cancellation (SolverOptions::cancel, TrainStepperOptions::cancel, TrainTableOptions::cancel and
// the references' options): every long phase of a run, its set-up included, polls the flag and
// ends with RunCancelled within one of its steps (a segment, a grid segment, a CVODE step).
// Tolerance of the timed cases: kCancelBoundSeconds (support/cancel_latency.h) from the set to
// the throw. Each phase here runs for many seconds uncancelled (stated per case) and its steps
// last at most ~0.1 s; the rest is margin for a loaded CI machine.
#include <atomic>
#include <catch2/catch.hpp>

#include "gearnvh/solver/cycle_map.h"
#include "gearnvh/solver/cycle_output_rows.h"
#include "gearnvh/solver/exact_recorder.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/reference_integrator.h"
#include "gearnvh/solver/segment_runs.h"
#include "gearnvh/solver/train_cycle_map.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_segment_runs.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/solver_fixture.h"
#include "support/cancel_latency.h"

namespace gearnvh::testing {
namespace {

// The flexible pair at N40 full (state dimension 82): every table build is slow per segment.
GearboxSpec SlowPairSpec(int segments_per_cycle) {
  GearboxSpec spec = FlexibleShaftsPair();
  spec.analysis.segments_per_cycle = segments_per_cycle;
  return spec;
}

// The elastic two-stage train at tier 5 with its loose gear rattling under engine order 2.
TrainSpec SlowTrainSpec() {
  TrainSpec spec = ElasticTwoStage();
  spec.operating.excitation = {{2.0, 3000.0, 0.0}};
  return spec;
}

TEST_CASE("a set cancel flag stops every table build of a pair run before its first step") {
  const SolverSetup s(IdleRattleSpec(), Tier::kTier1);
  SegmentTables quiet = s.tables;
  quiet.excitation.clear();
  std::atomic<bool> set{true};
  CHECK_THROWS_AS(BuildSegmentTables(s.model, s.reduced, s.spec, &set), RunCancelled);
  CHECK_THROWS_AS(SegmentRunTable(s.tables, ContactState::kDrive, 5, &set), RunCancelled);
  Trajectory out;
  CHECK_THROWS_AS(ExactRecorder(s.tables, 32, &out, &set), RunCancelled);
  CHECK_THROWS_AS(ConstantContactCycle(quiet, ContactState::kDrive, &set), RunCancelled);
  const ConstantContactCycle cycle(quiet, ContactState::kDrive);
  const ExactRecorder recorder(quiet, 32, &out);
  CHECK_THROWS_AS(CycleOutputRows(quiet, cycle, recorder, 32, &set), RunCancelled);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions options;
  options.cancel = &set;
  for (const LadderMethod method : kLadderMethods) {
    ApplyLadderMethod(method, options);
    CHECK_THROWS_AS(ExactStepper(s.tables, options, z0, state0, 0, 0).Run(1, false), RunCancelled);
  }
  ReferenceOptions reference;
  reference.cancel = &set;
  CHECK_THROWS_AS(SimulateReference(s.tables, z0, state0, reference), RunCancelled);
}

TEST_CASE("a set cancel flag stops every table build of a train run before its first step") {
  const TrainSpec spec = RattlerTrain(1500.0);
  const GearTrain train = BuildGearTrain(spec);
  std::atomic<bool> set{true};
  TrainTableOptions table_options;
  table_options.cancel = &set;
  CHECK_THROWS_AS(BuildTrainTables(spec, train, table_options), RunCancelled);
  const TrainTables tables = BuildTrainTables(spec, train);
  const std::vector<ContactState> drive(tables.meshes.size(), ContactState::kDrive);
  CHECK_THROWS_AS(TrainCycleMap(tables, drive, 0.01, 1000, &set), RunCancelled);
  const auto [z0, states0] = TrainStaticState(tables);
  REQUIRE(tables.common_period > 0.0);  // segment-run fusion applies
  TrainSegmentRuns runs(tables, 5, size_t{64} << 20, 100000, &set);
  TrainGrid grid(tables);
  Eigen::VectorXd z = z0;
  CHECK_THROWS_AS(runs.Advance(0, states0, 1.0, true, grid, z), RunCancelled);
  TrainReferenceOptions reference;
  reference.cancel = &set;
  CHECK_THROWS_AS(SimulateTrainReference(tables, z0, states0, reference), RunCancelled);
}

TEST_CASE("cancelling a pair's table build at N40 full ends it within a second") {
  // 256 segments at state dimension 82: about 10 s uncancelled (3 expm pairs and an
  // eigenproblem per segment).
  const GearboxSpec spec = SlowPairSpec(256);
  const ComponentModel model = BuildComponentModel(spec);
  const ReducedModel reduced = ReduceModel(model, Tier::kTier5);
  const double seconds = SecondsToCancel(0.3, [&](const std::atomic<bool>* cancel) {
    BuildSegmentTables(model, reduced, spec, cancel);
  });
  CHECK(seconds < kCancelBoundSeconds);
}

TEST_CASE("cancelling a pair run at N40 full ends it within a second, early or late") {
  // The stepper's tables (segment runs, recorder rows), the first cycle's decompositions (one per
  // visited segment and state, ~1 s in all) and the stepping: over 5 s for 10^5 cycles.
  // Built once for the three delays (the tier-5 reduction is ~25 s in the instrumented build).
  static const SolverSetup s(SlowPairSpec(64), Tier::kTier5);
  const auto start = StaticInitialState(s.tables);
  SolverOptions options;
  options.cycles = 100000;
  options.max_trajectory_samples = 4096;  // the statistics are of every cycle; no 200 MB record
  const double delay = GENERATE(0.05, 0.5, 2.0);
  INFO("flag set " << delay << " s after the start");
  const double seconds = SecondsToCancel(delay, [&](const std::atomic<bool>* cancel) {
    SolverOptions run = options;
    run.cancel = cancel;
    SimulateExact(s.tables, start.first, start.second, run);
  });
  CHECK(seconds < kCancelBoundSeconds);
}

TEST_CASE("cancelling a CVODE reference run ends it within a second") {
  const SolverSetup s(IdleRattleSpec(), Tier::kTier1);
  const auto start = StaticInitialState(s.tables);
  ReferenceOptions options;
  options.cycles = 1000000;  // hours at rtol 1e-12
  const double seconds = SecondsToCancel(0.3, [&](const std::atomic<bool>* cancel) {
    ReferenceOptions run = options;
    run.cancel = cancel;
    SimulateReference(s.tables, start.first, start.second, run);
  });
  CHECK(seconds < kCancelBoundSeconds);
}

TEST_CASE("cancelling a train's cycle map, fused-run tables or CVODE run ends it within a second") {
  const TrainSpec spec = SlowTrainSpec();
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables tables = BuildTrainTablesAtTier(spec, train, Tier::kTier5);
  const long segments = CountCommonPeriodSegments(tables, 1000000);
  INFO("state dimension " << tables.m << ", " << segments << " grid segments per common period");
  SECTION("the cycle map") {
    const std::vector<ContactState> drive(tables.meshes.size(), ContactState::kDrive);
    const double seconds = SecondsToCancel(0.3, [&](const std::atomic<bool>* cancel) {
      const TrainCycleMap map(tables, drive, 0.01, segments, cancel);
    });
    CHECK(seconds < kCancelBoundSeconds);
  }
  const auto start = TrainStaticState(tables);
  SECTION("the fused-run tables") {
    // Stepping and offering every grid segment to segment-run fusion, whose table builds take
    // most of the time (the fusion row of the validation ladder).
    const double seconds = SecondsToCancel(0.3, [&](const std::atomic<bool>* cancel) {
      CheckSegmentRuns(tables, tables, start.first, start.second, 1000000, EventMethod::kSpectral,
                       cancel);
    });
    CHECK(seconds < kCancelBoundSeconds);
  }
  SECTION("CVODE") {
    TrainReferenceOptions options;
    options.end_time = 100.0;
    const double seconds = SecondsToCancel(0.3, [&](const std::atomic<bool>* cancel) {
      TrainReferenceOptions run = options;
      run.cancel = cancel;
      SimulateTrainReference(tables, start.first, start.second, run);
    });
    CHECK(seconds < kCancelBoundSeconds);
  }
}

}  // namespace
}  // namespace gearnvh::testing
