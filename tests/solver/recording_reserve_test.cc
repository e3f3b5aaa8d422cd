// PlanRecording (run_recording.h): the memory a run reserves for its recording, known before the
// run, against what the run then holds.
#include <catch2/catch.hpp>

#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/run_recording.h"
#include "solver/solver_fixture.h"

namespace gearnvh {
namespace {

TEST_CASE("PlanRecording is what a run records: every sample and the events it logs",
          "[solver][recorder][memory]") {
  // Idle rattle: impacts on both flanks, so the event log is used too.
  const testing::SolverSetup s(testing::IdleRattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions options;
  options.cycles = 40;
  options.transient_cycles = 20;
  // Counts, so no tolerance: the recorder takes samples_per_cycle samples per recorded cycle at
  // t_k = k T / samples_per_cycle from the window's start (the window's end excluded), into the
  // buffer reserved once before the run.
  SECTION("within the bounds: every sample and every event kept") {
    const RecordingReserve plan = PlanRecording(options);
    const SolverResult run = SimulateExact(s.tables, z0, state0, options);
    const Trajectory& t = run.trajectory;
    CHECK(plan.samples == 40 * options.samples_per_cycle);
    CHECK(static_cast<long>(t.samples.size()) == plan.samples);
    CHECK(t.samples.capacity() * sizeof(TrajectorySample) == plan.sample_bytes());
    // The log reserves 16 events per cycle; the rattle has fewer, all logged.
    REQUIRE(run.summary.events > 0);
    CHECK(static_cast<long>(t.events.size()) == run.summary.events);
    CHECK(run.summary.events <= plan.events);
    CHECK(t.events.capacity() * sizeof(EventRecord) == plan.event_bytes());
    CHECK(plan.bytes() == plan.sample_bytes() + plan.event_bytes());
    CHECK_FALSE(run.summary.trajectory_truncated);
  }
  SECTION("at the bounds: the buffers stop there and the run says so") {
    options.max_trajectory_samples = 500;
    options.max_logged_events = 3;
    const RecordingReserve plan = PlanRecording(options);
    CHECK(plan.samples == 500);
    CHECK(plan.events == 3);
    const SolverResult run = SimulateExact(s.tables, z0, state0, options);
    CHECK(run.trajectory.samples.size() == 500);
    CHECK(run.trajectory.events.size() == 3);
    CHECK(run.trajectory.samples.capacity() * sizeof(TrajectorySample) == plan.sample_bytes());
    CHECK(run.summary.trajectory_truncated);
  }
  SECTION("without a recorded trajectory no sample is reserved") {
    options.record_trajectory = false;
    const RecordingReserve plan = PlanRecording(options);
    CHECK(plan.samples == 0);
    const SolverResult run = SimulateExact(s.tables, z0, state0, options);
    CHECK(run.trajectory.samples.empty());
  }
}

}  // namespace
}  // namespace gearnvh
