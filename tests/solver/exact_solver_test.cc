#include "gearnvh/solver/exact_solver.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/solver/reference_integrator.h"
#include "model/test_specs.h"
#include "solver/solver_fixture.h"
#include "support/allocation_counter.h"

namespace gearnvh {
namespace {

using testing::StandardPair;
using Setup = testing::SolverSetup;

GearboxSpec RattleSpec(double amplitude = 1500.0) { return testing::IdleRattleSpec(amplitude); }

double MaxTeDifference(const Trajectory& a, const Trajectory& b, double* scale) {
  double diff = 0.0, max_te = 0.0;
  const size_t n = std::min(a.samples.size(), b.samples.size());
  for (size_t i = 0; i < n; ++i) {
    diff = std::max(diff, std::abs(a.samples[i].te - b.samples[i].te));
    max_te = std::max(max_te, std::abs(a.samples[i].te));
  }
  *scale = max_te;
  return diff;
}

// Conformance: every event path (V1, V2, V3) against the same tight reference.
TEST_CASE("every event method agrees with a tight CVODE reference on a strong-rattle run",
          "[solver][reference]") {
  const Setup s(RattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions opt;
  ApplyLadderMethod(GENERATE(from_range(std::begin(kLadderMethods), std::end(kLadderMethods))),
                    opt);
  INFO("events " << EventMethodName(opt.events) << ", " << SolverMethodName(opt.method));
  opt.cycles = 50;
  const SolverResult exact = SimulateExact(s.tables, z0, state0, opt);
  ReferenceOptions ref_opt;
  ref_opt.cycles = 50;
  ref_opt.rtol = 1e-13;
  const ReferenceResult ref = SimulateReference(s.tables, z0, state0, ref_opt);
  REQUIRE(ref.status == ReferenceStatus::kSuccess);
  REQUIRE(exact.summary.status == SolverStatus::kSuccess);
  // Double-sided rattle: impacts on both flanks (45 drive impacts in the 50 cycles when the engine
  // order became exact, 2026-12-05).
  CHECK(exact.summary.drive_impacts > 35);
  CHECK(exact.summary.back_impacts >= 5);
  // The same event sequence, every one of the 50 cycles.
  REQUIRE(exact.trajectory.events.size() == ref.trajectory.events.size());
  const double segment = s.tables.SegmentLength(0);
  for (size_t i = 0; i < exact.trajectory.events.size(); ++i) {
    const EventRecord& a = exact.trajectory.events[i];
    const EventRecord& b = ref.trajectory.events[i];
    INFO("event " << i << " at " << a.time);
    CHECK(a.to == b.to);
    CHECK(a.from == b.from);
    // Within the first 10 cycles the reference's own error (rtol 1e-13, amplified by slow
    // separations where dt = dg / g') bounds the difference: 1e-5 of a segment. Later, the
    // rattle's sensitivity to initial error grows it ~40x per 10 cycles (measured): an
    // exponential budget 1e-5 * 40^((t - 10 T) / 10 T) up to cycle 30. Beyond, sensitivity (not
    // either solver) dominates; there only the event sequence is compared.
    const double cycles = a.time / s.tables.mesh_period;
    if (cycles < 30) {
      const double bound = cycles < 10 ? 1e-5 : 1e-5 * std::pow(40.0, (cycles - 10) / 10);
      CHECK(std::abs(a.time - b.time) <= bound * segment);
    }
  }
  // TE over the first 10 cycles within the 1e-8 relative (measured ~1e-9).
  Trajectory first_ten_exact = exact.trajectory, first_ten_ref = ref.trajectory;
  first_ten_exact.samples.resize(10 * static_cast<size_t>(opt.samples_per_cycle));
  first_ten_ref.samples.resize(10 * static_cast<size_t>(ref_opt.samples_per_cycle));
  double scale = 0.0;
  const double diff = MaxTeDifference(first_ten_exact, first_ten_ref, &scale);
  CHECK(diff <= 1e-8 * scale);
}

TEST_CASE(
    "exact solver agrees with CVODE to 1e-8 on TE over 20 excited cycles in permanent contact",
    "[solver][reference]") {
  const Setup s(RattleSpec(400.0), Tier::kTier1);  // excitation below the separation threshold
  const auto [z0, state0] = StaticInitialState(s.tables);
  REQUIRE(state0 == ContactState::kDrive);
  SolverOptions opt;
  opt.cycles = 20;
  const SolverResult exact = SimulateExact(s.tables, z0, state0, opt);
  ReferenceOptions ref_opt;
  ref_opt.cycles = 20;
  ref_opt.rtol = 1e-13;
  const ReferenceResult ref = SimulateReference(s.tables, z0, state0, ref_opt);
  CHECK(exact.trajectory.events.empty());
  CHECK(ref.trajectory.events.empty());
  double scale = 0.0;
  const double diff = MaxTeDifference(exact.trajectory, ref.trajectory, &scale);
  INFO("max |TE difference| " << diff << " m, max |TE| " << scale << " m");
  CHECK(diff <= 1e-8 * scale);
}

TEST_CASE("results do not depend on the sub-step length (exact propagation)", "[solver][exact]") {
  // Quartering every sub-step (propagators from a 30-term Taylor series instead of the Pade
  // exponential) changes only rounding. Over 20 rattle cycles the differences stay at the level of
  // rounding amplified by the dynamics (measured 3e-10 on TE, 1.4e-8 of a segment on event times):
  // bounds 1e-9 relative on TE, 1e-7 of a segment.
  const Setup s(RattleSpec(), Tier::kTier1);
  SegmentTables fine = s.tables;
  for (int j = 0; j < fine.segments(); ++j) {
    fine.substeps[j] *= 4;
    const double d = fine.SegmentLength(j) / fine.substeps[j];
    for (SegmentSystem& sys : fine.systems[j]) {
      Eigen::MatrixXd sum = Eigen::MatrixXd::Identity(fine.m, fine.m), term = sum;
      for (int k = 1; k <= 30; ++k) {
        term = (term * sys.A * d / k).eval();
        sum += term;
      }
      sys.substep = sum;
    }
  }
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions opt;
  opt.cycles = 20;
  const SolverResult a = SimulateExact(s.tables, z0, state0, opt);
  const SolverResult b = SimulateExact(fine, z0, state0, opt);
  REQUIRE(a.trajectory.events.size() == b.trajectory.events.size());
  REQUIRE(a.trajectory.events.size() > 20);
  for (size_t i = 0; i < a.trajectory.events.size(); ++i) {
    CHECK(std::abs(a.trajectory.events[i].time - b.trajectory.events[i].time) <=
          1e-7 * s.tables.SegmentLength(0));
  }
  double scale = 0.0;
  const double diff = MaxTeDifference(a.trajectory, b.trajectory, &scale);
  INFO("max |TE difference| " << diff << " m, max |TE| " << scale << " m, events "
                              << a.trajectory.events.size());
  CHECK(diff <= 1e-9 * scale);
}

TEST_CASE("free flight under constant drag is the closed-form parabola", "[solver][closed-form]") {
  // Tier 1, no excitation, constant mesh stiffness (e_j = 0): in the backlash the only forces are
  // the drive torque T r_b1/r_b2 on the pinion and the drag T on the wheel, so
  //   delta'' = r_b1 (T r_b1/r_b2) / J1 + r_b2 T / J2 = const,
  // and from rest at delta = 0 the drive flank is hit at t* = sqrt(2 b / delta'').
  GearboxSpec spec = StandardPair(27, 43);
  spec.operating.torque = 0.3;
  spec.mesh.stiffness = FourierStiffness{2.5e8, {}, {}};
  Setup s(spec, Tier::kTier1);
  const double rb1 = s.model.geometry.pinion.base, rb2 = s.model.geometry.wheel.base;
  const double j1 = s.reduced.M(0, 0), j2 = s.reduced.M(1, 1);
  const double T = spec.operating.torque, b = s.tables.half_backlash;
  const double accel = rb1 * (T * rb1 / rb2) / j1 + rb2 * T / j2;
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(s.tables.m);
  z0[2 * s.tables.n] = 1.0;
  SolverOptions opt;
  opt.cycles = 3;
  const SolverResult r = SimulateExact(s.tables, z0, ContactState::kFree, opt);
  REQUIRE_FALSE(r.trajectory.events.empty());
  const double t_hit = std::sqrt(2.0 * b / accel);
  // Exact to rounding: the event time is a root of the same quadratic (16 ulps).
  CHECK(r.trajectory.events[0].time == Approx(t_hit).epsilon(1e-13));
  CHECK(r.trajectory.events[0].to == ContactState::kDrive);
  CHECK(r.trajectory.events[0].gap_rate == Approx(accel * t_hit).epsilon(1e-12));
  for (const TrajectorySample& p : r.trajectory.samples) {
    if (p.time >= t_hit) break;
    CHECK(p.te == Approx(0.5 * accel * p.time * p.time).epsilon(1e-12).margin(1e-22));
  }
}

TEST_CASE("permanent contact with constant stiffness settles on the static closed form",
          "[solver][closed-form]") {
  // Drive contact, constant k, no excitation: the steady state is k (delta - b) = F = T / r_b2,
  // delta = b + F / k, reached from a perturbed start as the mesh mode decays (zeta = 0.05 at
  // ~7.7 kHz: e^-24 per 4 cycles), so after 40 cycles only rounding remains.
  GearboxSpec spec = StandardPair(27, 43);
  spec.operating.torque = 20.0;
  spec.mesh.stiffness = FourierStiffness{2.5e8, {}, {}};
  Setup s(spec, Tier::kTier1);
  auto [z0, state0] = StaticInitialState(s.tables);
  REQUIRE(state0 == ContactState::kDrive);
  z0[s.tables.n] += 0.01;  // kick the pinion speed
  SolverOptions opt;
  opt.cycles = 40;
  const SolverResult r = SimulateExact(s.tables, z0, state0, opt);
  CHECK(r.trajectory.events.empty());
  const double F = spec.operating.torque / s.model.geometry.wheel.base;
  const double expected = s.tables.half_backlash + F / 2.5e8;
  CHECK(r.trajectory.samples.back().te == Approx(expected).epsilon(1e-12));
  CHECK(r.trajectory.samples.back().mesh_force == Approx(F).epsilon(1e-9));
}

TEST_CASE("the stepping loop does not allocate, for every locator", "[solver][allocation]") {
  const Setup s(RattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  const LadderMethod method =
      GENERATE(from_range(std::begin(kLadderMethods), std::end(kLadderMethods)));
  INFO(LadderMethodName(method));
  SolverOptions opt;
  ApplyLadderMethod(method, opt);
  ExactStepper stepper(s.tables, opt, z0, state0, /*reserve_samples=*/100 * 32,
                       /*reserve_events=*/1000);
  // Warm-up outside the counted region: the counted run once, so that the V3 decompositions and
  // carry matrices of every (segment, state) it visits (carried only on unrecorded cycles) and the
  // segment runs its certificates reach exist (all built on first use), then the same run.
  stepper.Run(5, true);
  stepper.Run(50, true);
  stepper.Run(20, false);
  stepper.Restart(z0, state0);
  stepper.Run(5, true);
  testing::AllocationCounter counter;
  REQUIRE(stepper.Run(50, true));
  REQUIRE(stepper.Run(20, false));
  CHECK(counter.count() == 0);
  CHECK(stepper.summary().events > 50);  // the run did rattle (event path exercised)
}

TEST_CASE("the stepping loop with a tangent attached does not allocate, for every locator",
          "[solver][allocation]") {
  const Setup s(RattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  const LadderMethod method = GENERATE(LadderMethod::kV1, LadderMethod::kV2, LadderMethod::kV3);
  INFO(LadderMethodName(method));
  SolverOptions opt;
  ApplyLadderMethod(method, opt);
  ExactStepper stepper(s.tables, opt, z0, state0, 100 * 32, 1000);
  Eigen::MatrixXd tangent = Eigen::MatrixXd::Zero(s.tables.m, 2 * s.tables.n);
  tangent.topRows(2 * s.tables.n).setIdentity();
  stepper.AttachTangent(&tangent);
  stepper.Run(35, true);  // every visited (segment, state) gets its tables (built on first visit)
  stepper.Restart(z0, state0);
  stepper.Run(5, true);
  testing::AllocationCounter counter;
  REQUIRE(stepper.Run(30, true));
  CHECK(counter.count() == 0);
  CHECK(stepper.summary().events > 30);
  CHECK(tangent.allFinite());
}

TEST_CASE("V1, V2 and V3 agree on every event time of a strong-rattle run", "[solver][events]") {
  // Three independent event locators on the same exact propagation: dense dyadic propagators
  // (times quantised to D 2^-34), the Taylor polynomial with Newton on sub-steps, and the
  // closed-form spectral gap per segment. The bound, 1e-9 of a segment, holds for the first
  // 10 cycles (measured <= 4e-10, V1's quantisation); afterwards the rattle's sensitivity amplifies
  // rounding-level differences (~10x per 10 cycles here), so over 50 cycles the event sequence
  // (which flank, in order) is compared, with times within 1e-6 of a segment up to cycle 30.
  const testing::SolverSetup s(RattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  const auto pair = GENERATE(std::make_pair(LadderMethod::kV1, LadderMethod::kV2),
                             std::make_pair(LadderMethod::kV2, LadderMethod::kV3),
                             std::make_pair(LadderMethod::kV1, LadderMethod::kV3));
  INFO(LadderMethodName(pair.first) << " vs " << LadderMethodName(pair.second));
  SolverOptions first, second;
  ApplyLadderMethod(pair.first, first);
  ApplyLadderMethod(pair.second, second);
  first.cycles = second.cycles = 50;
  const SolverResult a = SimulateExact(s.tables, z0, state0, first);
  const SolverResult b = SimulateExact(s.tables, z0, state0, second);
  REQUIRE(a.trajectory.events.size() == b.trajectory.events.size());
  REQUIRE(a.trajectory.events.size() > 100);
  const double segment = s.tables.SegmentLength(0);
  double worst_first_ten = 0.0;
  for (size_t i = 0; i < a.trajectory.events.size(); ++i) {
    const EventRecord& x = a.trajectory.events[i];
    const EventRecord& y = b.trajectory.events[i];
    INFO("event " << i << " at " << x.time);
    CHECK(x.to == y.to);
    CHECK(x.from == y.from);
    const double cycles = x.time / s.tables.mesh_period;
    if (cycles < 10) worst_first_ten = std::max(worst_first_ten, std::abs(x.time - y.time));
    if (cycles < 30) CHECK(std::abs(x.time - y.time) <= 1e-6 * segment);
  }
  CHECK(worst_first_ten <= 1e-9 * segment);
}

TEST_CASE("trajectory storage is bounded and the truncation is reported", "[solver][memory]") {
  const testing::SolverSetup s(RattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions opt;
  opt.method = SolverMethod::kStepped;
  opt.cycles = 20;
  opt.max_trajectory_samples = 100;  // fewer than 20 cycles x 32 segments
  opt.max_logged_events = 5;
  const SolverResult r = SimulateExact(s.tables, z0, state0, opt);
  CHECK(r.trajectory.samples.size() == 100);
  CHECK(r.trajectory.events.size() <= 5);
  CHECK(r.summary.events > 5);  // counts stay exact beyond the stored log
  CHECK(r.summary.trajectory_truncated);
  opt.max_trajectory_samples = 4'000'000;
  opt.max_logged_events = 1'000'000;
  CHECK_FALSE(SimulateExact(s.tables, z0, state0, opt).summary.trajectory_truncated);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("a set cancel flag stops a run at the next mesh cycle", "[solver][cancel]") {
  Setup s(testing::IdleRattleSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  std::atomic<bool> cancel{false};
  SolverOptions opt;
  opt.cycles = 20;
  opt.cancel = &cancel;
  // Unset: the flag changes nothing (the same run as without it, bit for bit).
  SolverOptions plain = opt;
  plain.cancel = nullptr;
  const SolverResult with_flag = SimulateExact(s.tables, z0, state0, opt);
  const SolverResult without = SimulateExact(s.tables, z0, state0, plain);
  REQUIRE(with_flag.trajectory.samples.size() == without.trajectory.samples.size());
  CHECK(with_flag.final_state == without.final_state);
  // Set (here from the progress callback after the first chunk): the run throws RunCancelled
  // instead of finishing its cycles.
  opt.cycles = 1000;
  long calls = 0;
  CHECK_THROWS_AS(SimulateExact(s.tables, z0, state0, opt,
                                [&](long, long) {
                                  ++calls;
                                  cancel.store(true);
                                }),
                  RunCancelled);
  CHECK(calls == 1);
}

}  // namespace
}  // namespace gearnvh
