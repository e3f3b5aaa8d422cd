#include "gearnvh/solver/exact_recorder.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/solver/reference_integrator.h"
#include "nvh/impact_oscillator.h"
#include "solver/solver_fixture.h"

namespace gearnvh {
namespace {

using testing::BuildOscillatorTables;
using testing::ImpactOscillator;

TEST_CASE("exact statistics of one piece equal the closed forms of a sinusoid",
          "[solver][recorder]") {
  // In drive contact, undamped, no force: x'' = -w^2 (x - b), so x(t) = b + A cos(w t + phi).
  // The piece spans 0.73 of a 1 ms segment with w h = 2 pi (16 sub-steps, so the piece is cut into
  // chunks); phi is chosen so the maximum b + A and the minimum b - A both fall inside, between
  // sub-step boundaries.
  ImpactOscillator o;
  o.mass = 2.0;
  const double w = 2 * std::numbers::pi * 1000.0;
  o.stiffness = o.mass * w * w;
  o.half_backlash = 1e-4;
  o.boundaries = {0.0, 1e-3};
  o.forces = {0.0};
  SegmentTables t = BuildOscillatorTables(o);
  t.wheel_rate_row = t.te_rate_row;  // the "wheel speed" is x', its acceleration x''
  REQUIRE(t.substeps[0] == 16);
  const double A = 3e-6, b = o.half_backlash, phi = -0.4, L = 0.73e-3;
  Eigen::VectorXd z(4);
  z << b + A * std::cos(phi), -A * w * std::sin(phi), 1.0, 0.0;
  Trajectory out;
  out.samples.reserve(64);
  ExactRecorder recorder(t, 40, &out);  // samples every 25 us
  recorder.Start(0.0);
  recorder.Piece(0, ContactState::kDrive, 0.0, L, z);
  const TrajectoryStatistics& st = out.statistics;
  REQUIRE(st.duration == L);
  CHECK(st.chunks == 12);  // ceil(0.73 * 16)

  const double u0 = phi, u1 = w * L + phi;
  const double mean = b + A * (std::sin(u1) - std::sin(u0)) / (w * L);
  const double square = b * b + 2 * b * A * (std::sin(u1) - std::sin(u0)) / (w * L) +
                        A * A * (0.5 + (std::sin(2 * u1) - std::sin(2 * u0)) / (4 * w * L));
  const double rms = std::sqrt(square - mean * mean);
  // Rounding of a degree-18 polynomial per chunk (rho D <= 1/2): relative 1e-12 of the
  // fluctuation is a few hundred ulps of b, which carries it.
  CHECK(st.te.Mean(L) == Approx(mean).epsilon(1e-13));
  CHECK(st.te.Rms(L) == Approx(rms).epsilon(1e-10));
  CHECK(st.te.max == Approx(b + A).epsilon(1e-15));
  CHECK(st.te.min == Approx(b - A).epsilon(1e-15));
  CHECK(st.te.time_of_max == Approx(-phi / w).epsilon(1e-9));
  CHECK(st.te.time_of_min == Approx((std::numbers::pi - phi) / w).epsilon(1e-9));
  // Mesh force k (x - b): its maximum k A between sub-step boundaries, mean k (mean - b).
  CHECK(st.mesh_force.max == Approx(o.stiffness * A).epsilon(1e-12));
  CHECK(st.mesh_force.Mean(L) == Approx(o.stiffness * (mean - b)).margin(1e-9 * o.stiffness * A));
  // Acceleration x'' = -w^2 (x - b): RMS w^2 times the RMS of x about its mean... of (x - b).
  CHECK(st.wheel_acceleration.Rms(L) == Approx(w * w * rms).epsilon(1e-9));
  // Uniform samples are the exact solution at their times.
  REQUIRE(out.samples.size() == 30);  // t = 0, 25 us, ..., 725 us < L
  for (const TrajectorySample& s : out.samples) {
    CHECK(s.te == Approx(b + A * std::cos(w * s.time + phi)).epsilon(1e-15));
    CHECK(s.te_rate == Approx(-A * w * std::sin(w * s.time + phi)).margin(1e-12 * A * w));
  }
}

TEST_CASE("a peak between segment boundaries is found, not missed", "[solver][recorder]") {
  // Many short pieces (as events cut a segment) each starting where the last ended: the running
  // maximum over all of them is the sinusoid's, whichever piece holds the peak.
  ImpactOscillator o;
  const double w = 2 * std::numbers::pi * 50.0;
  o.stiffness = w * w;
  o.half_backlash = 0.0;
  o.boundaries = {0.0, 0.02};
  o.forces = {0.0};
  const SegmentTables t = BuildOscillatorTables(o);
  Trajectory out;
  ExactRecorder recorder(t, 1, &out);
  recorder.Start(0.0);
  Eigen::VectorXd z(4);
  z << 1.0, 0.0, 1.0, 0.0;  // x = cos(w t): peaks at t = 0, 20 ms; troughs at 10 ms
  const Eigen::MatrixXd& A = t.systems[0][static_cast<int>(ContactState::kDrive)].A;
  double start = 0.0;
  for (double length : {0.0031, 0.0042, 0.0053, 0.0044}) {  // the trough at 10 ms lies inside
    recorder.Piece(0, ContactState::kDrive, start, length, z);
    z = BalancedExpm(A, length, 1, w) * z;
    start += length;
  }
  CHECK(out.statistics.te.min == Approx(-1.0).epsilon(1e-14));
  CHECK(out.statistics.te.time_of_min == Approx(0.01).epsilon(1e-10));
  CHECK(out.statistics.duration == Approx(0.017).epsilon(1e-15));
}

void CheckAgainstDenseReference(const SegmentTables& tables, const Eigen::VectorXd& z0,
                                ContactState state0, long cycles, long min_events,
                                double sample_tolerance) {
  SolverOptions options;
  options.method = SolverMethod::kStepped;
  options.cycles = cycles;
  const SolverResult exact = SimulateExact(tables, z0, state0, options);
  REQUIRE(exact.summary.status == SolverStatus::kSuccess);
  CHECK(exact.summary.events >= min_events);
  ReferenceOptions ref_options;
  ref_options.cycles = cycles;
  ref_options.rtol = 1e-13;
  const ReferenceResult ref = SimulateReference(tables, z0, state0, ref_options);
  REQUIRE(ref.status == ReferenceStatus::kSuccess);
  const TrajectoryStatistics& st = exact.trajectory.statistics;
  const TrajectoryStatistics& d = ref.trajectory.statistics;
  const double T = st.duration;
  REQUIRE(d.duration == Approx(T).epsilon(1e-14));
  INFO("TE RMS exact " << st.te.Rms(T) << " dense " << d.te.Rms(T) << "; p-p exact "
                       << st.te.max - st.te.min << " dense " << d.te.max - d.te.min
                       << "; force max exact " << st.mesh_force.max << " dense " << d.mesh_force.max
                       << "; force mean exact " << st.mesh_force.Mean(T) << " dense "
                       << d.mesh_force.Mean(T));
  // The bound: 1e-6 relative. The dense reference carries CVODE's own error (rtol 1e-13,
  // ~1e-9 on TE, more where a slow separation amplifies event-time errors).
  CHECK(st.te.Rms(T) == Approx(d.te.Rms(T)).epsilon(1e-6));
  CHECK(st.te.Mean(T) == Approx(d.te.Mean(T)).epsilon(1e-6));
  CHECK(st.te.max - st.te.min == Approx(d.te.max - d.te.min).epsilon(1e-6));
  CHECK(st.mesh_force.max == Approx(d.mesh_force.max).epsilon(1e-6));
  CHECK(st.mesh_force.Mean(T) == Approx(d.mesh_force.Mean(T)).epsilon(1e-6));
  CHECK(st.wheel_acceleration.Rms(T) == Approx(d.wheel_acceleration.Rms(T)).epsilon(1e-6));
  // Samples at the same times agree with CVODE's interpolant.
  REQUIRE(exact.trajectory.samples.size() == static_cast<size_t>(cycles * 32));
  REQUIRE(ref.trajectory.samples.size() == exact.trajectory.samples.size());
  double worst = 0.0, scale = 0.0;
  for (size_t i = 0; i < exact.trajectory.samples.size(); ++i) {
    const TrajectorySample& a = exact.trajectory.samples[i];
    const TrajectorySample& b = ref.trajectory.samples[i];
    CHECK(a.time == Approx(b.time).margin(1e-15));
    worst = std::max(worst, std::abs(a.te - b.te));
    scale = std::max(scale, std::abs(a.te));
  }
  INFO("worst sample difference " << worst << " m of " << scale << " m");
  CHECK(worst <= sample_tolerance * scale);
}

TEST_CASE("exact TE and force statistics agree with a dense reference to 1e-6",
          "[solver][recorder][reference]") {
  SECTION("a loaded pair with a measured rectangular stiffness (no events)") {
    GearboxSpec spec = testing::StandardPair(27, 43);
    spec.mesh.stiffness = RectangularStiffness{2.0e8, 3.4e8, 1.43};
    spec.operating.torque = 50.0;
    spec.operating.speed = 2000.0 * 2 * std::numbers::pi / 60;  // 900 Hz mesh: a dynamic response
    const testing::SolverSetup s(spec, Tier::kTier1);
    // No events: the samples agree to CVODE's accuracy, the ladder's 1e-8.
    CheckAgainstDenseReference(s.tables, DriveEquilibrium(s.tables), ContactState::kDrive, 12, 0,
                               1e-8);
  }
  SECTION("idle rattle (impacts on both flanks)") {
    const testing::SolverSetup s(testing::IdleRattleSpec(), Tier::kTier1);
    const auto [rest, rest_state] = StaticInitialState(s.tables);
    // Settle into rattle first; both then start from the same rattling state (the solvers agree
    // to ~1e-9 over a few cycles before the rattle's sensitivity takes over).
    SolverOptions settle;
    settle.cycles = 1;
    settle.transient_cycles = 200;
    settle.record_trajectory = false;
    const SolverResult settled = SimulateExact(s.tables, rest, rest_state, settle);
    // Pointwise, CVODE's event times (1e-5 of a segment, exact_solver_test) move the samples
    // after an event by ~gap rate x that, which the rattle then grows (~40x per 10 cycles,
    // exact_solver_test) over the 6 cycles: 1e-5 of the TE (measured 3.7e-6).
    CheckAgainstDenseReference(s.tables, settled.final_state, settled.final_contact, 6, 8, 1e-5);
  }
}

}  // namespace
}  // namespace gearnvh
