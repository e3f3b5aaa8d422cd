// Segment-run fusion (docs/design.md §4.5): certified products of consecutive segment propagators
// give the step-by-step state to rounding (the ladder's bound: 1e-12 relative).
#include <catch2/catch.hpp>

#include "solver/solver_fixture.h"

namespace gearnvh {
namespace {

using testing::SolverSetup;

struct Pair {
  ExactStepper stepped, fused;
};

// The same start through V3 stepping and through V3 with segment runs, `cycles` unrecorded.
void CompareFusedRuns(const SegmentTables& t, long cycles, double tolerance, long* fused_segments) {
  const auto [z0, s0] = StaticInitialState(t);
  SolverOptions stepped, fused;
  ApplyLadderMethod(LadderMethod::kV3, stepped);
  ApplyLadderMethod(LadderMethod::kFused, fused);
  // Runs reproduce the dense propagators' products: compared with dense stepping on both sides
  // (V3's carry in decoupled coordinates has its own test, event_locator_test.cc).
  stepped.carry_max_error = 0.0;
  fused.carry_max_error = 0.0;
  ExactStepper a(t, stepped, z0, s0, 0, 0), b(t, fused, z0, s0, 0, 0);
  REQUIRE(a.Run(cycles, false));
  REQUIRE(b.Run(cycles, false));
  *fused_segments = b.summary().run_fused_segments;
  CHECK(a.contact() == b.contact());
  const Eigen::VectorXd ea = ElasticPart(t, a.state()), eb = ElasticPart(t, b.state());
  INFO("relative difference " << (ea - eb).norm() / ea.norm() << ", fused segments "
                              << *fused_segments << " of " << cycles * t.segments());
  CHECK((ea - eb).norm() <= tolerance * ea.norm());
  CHECK(b.summary().matvecs < a.summary().matvecs);
}

TEST_CASE("segment runs: a loaded, excited pair equals step-by-step to 1e-12", "[solver][runs]") {
  // The whine gearbox with an engine order: permanent contact, but the excitation rules out the
  // constant-contact cycle map, so only certified runs fuse (where the excitation's acceleration
  // and the stiffness steps leave room). Not chaotic: differences stay at rounding over 200 cycles.
  GearboxSpec spec = testing::StandardPair(25, 75, 3e-3, 30e-3);
  spec.operating.torque = 300.0;
  spec.operating.excitation = {{2.0, 800.0, 0.3}};
  const SolverSetup s(spec, Tier::kTier1);
  long fused = 0;
  CompareFusedRuns(s.tables, 200, 1e-12, &fused);
  CHECK(fused > 0);
}

TEST_CASE("segment runs: rattle with impacts equals step-by-step to 1e-12 over 8 cycles",
          "[solver][runs]") {
  // Free flights between impacts are fused; contact changes fall back to the V3 event path. The
  // rattle is sensitive (errors grow ~x1.5 per cycle), so the comparison is over 8 cycles.
  const SolverSetup s(testing::IdleRattleSpec(), Tier::kTier1);
  long fused = 0;
  CompareFusedRuns(s.tables, 8, 1e-12, &fused);
  CHECK(fused > 0);
}

TEST_CASE("segment runs: recorded cycles keep every segment-boundary sample", "[solver][runs]") {
  const SolverSetup s(testing::IdleRattleSpec(), Tier::kTier1);
  const auto [z0, s0] = StaticInitialState(s.tables);
  SolverOptions fused;
  ApplyLadderMethod(LadderMethod::kFused, fused);
  fused.transient_cycles = 20;
  fused.cycles = 10;
  const SolverResult r = SimulateExact(s.tables, z0, s0, fused);
  CHECK(r.trajectory.samples.size() == static_cast<size_t>(10 * s.tables.segments()));
  CHECK(r.summary.run_fused_segments > 0);  // the transient used runs
}

}  // namespace
}  // namespace gearnvh
