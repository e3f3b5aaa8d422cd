#include "gearnvh/solver/cycle_map.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>

#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"
#include "solver/solver_fixture.h"

namespace gearnvh {
namespace {

using testing::StandardPair;
using Setup = testing::SolverSetup;

// The loaded industrial pair of examples/industrial_whine.yaml (permanent contact, no excitation).
GearboxSpec WhineSpec() {
  GearboxSpec s = StandardPair(25, 75, 4e-3, 40e-3);
  s.pinion.bore_diameter = 45e-3;
  s.wheel.bore_diameter = 80e-3;
  s.pinion.tip_relief = s.wheel.tip_relief = TipRelief{20e-6, 8e-3};
  s.mesh.backlash = 150e-6;
  s.mesh.damping_ratio = 0.07;
  s.mesh.friction_coefficient = 0.04;
  s.operating.speed = 1500 * 2 * 3.141592653589793 / 60;
  s.operating.torque = 1500;
  return s;
}

TEST_CASE("the fused cycle equals stepping the cycle and the orbit is periodic",
          "[solver][fused]") {
  for (Tier tier : {Tier::kTier1, Tier::kTier3}) {
    const Setup s(WhineSpec(), tier);
    const auto [z0, state0] = StaticInitialState(s.tables);
    REQUIRE(state0 == ContactState::kDrive);
    const ConstantContactCycle cycle(s.tables, ContactState::kDrive);
    REQUIRE(cycle.has_orbit());
    SolverOptions opt;
    opt.method = SolverMethod::kStepped;
    ExactStepper stepper(s.tables, opt, z0, state0, 0, 0);
    REQUIRE(stepper.Run(1, false));
    const Eigen::VectorXd fused = cycle.map() * z0;
    // Same propagators multiplied in another order: rounding of ~250 products. Positions are
    // compared relative to |x|, velocities relative to the natural rate omega_mesh |x| (the state's
    // velocity at the cycle end is much smaller than inside the cycle): 1e-12 each.
    const Eigen::VectorXd a = ElasticPart(s.tables, stepper.state()),
                          b = ElasticPart(s.tables, fused);
    const int n = s.tables.n;
    const double x_scale = a.head(n).norm();
    const double omega = ReferenceFrequency(s.tables.systems[0][2].A, n);
    INFO(TierName(tier) << ": positions " << (a - b).head(n).norm() / x_scale << ", velocities "
                        << (a - b).tail(n).norm() / (omega * x_scale));
    CHECK((a - b).head(n).norm() <= 1e-12 * x_scale);
    CHECK((a - b).tail(n).norm() <= 1e-12 * omega * x_scale);
    // One stepped cycle from the orbit returns to it.
    ExactStepper on_orbit(s.tables, opt, cycle.orbit(), ContactState::kDrive, 0, 0);
    REQUIRE(on_orbit.Run(1, false));
    const Eigen::VectorXd y = ElasticPart(s.tables, cycle.orbit());
    INFO(TierName(tier) << ": |orbit| " << y.norm() << ", |stepped - orbit| "
                        << (ElasticPart(s.tables, on_orbit.state()) - y).norm());
    // ~250 sub-step products in mixed units (m next to m/s, omega ~ 5e4): rounding is relative to
    // the largest velocity inside the cycle, not to the orbit's small start-of-cycle state
    // (measured ~2e-11): bound 1e-10.
    CHECK((ElasticPart(s.tables, on_orbit.state()) - y).norm() <= 1e-10 * y.norm());
    CHECK(on_orbit.summary().events == 0);
  }
}

TEST_CASE("a certified jump of 10^6 cycles equals applying the cycle map 10^6 times",
          "[solver][fused][jump]") {
  const Setup s(WhineSpec(), Tier::kTier1);
  auto [z0, state0] = StaticInitialState(s.tables);
  z0[s.tables.n] += 1e-3;  // a transient to decay
  const ConstantContactCycle cycle(s.tables, ContactState::kDrive);
  REQUIRE(cycle.Certify(z0).certified);
  Eigen::VectorXd z = z0;
  for (long k = 0; k < 1000000; ++k) {
    z = cycle.map() * z;
    // The free rotation drifts; remove it as the solver does (changes no gap).
    z.head(s.tables.n) -= s.tables.rigid_rotation * s.tables.recenter_row.dot(z.head(s.tables.n));
  }
  const Eigen::VectorXd jumped = cycle.Jump(z0, 1000000);
  const Eigen::VectorXd a = ElasticPart(s.tables, z), b = ElasticPart(s.tables, jumped);
  INFO("|product - jumped| " << (a - b).norm() << " of |z| " << z.head(2 * s.tables.n).norm());
  // Repeated products gain ~eps |z| of rounding per cycle (|z| grows with the free rotation's
  // speed, which residual dynamic friction changes): bound k * 4 eps |z| for k = 10^6.
  CHECK((a - b).norm() <=
        1e6 * 4 * std::numeric_limits<double>::epsilon() * z.head(2 * s.tables.n).norm());
  // The free rotation's speed, summed in closed form by the jump, equals the product's.
  const double va = s.tables.recenter_row.dot(z.segment(s.tables.n, s.tables.n));
  const double vb = s.tables.recenter_row.dot(jumped.segment(s.tables.n, s.tables.n));
  CHECK(vb == Approx(va).epsilon(1e-8));  // k eps |z| / |v| ~ 4e-9 of product rounding
  // And a shorter jump equals real sub-stepping (1000 cycles).
  SolverOptions opt;
  opt.method = SolverMethod::kStepped;
  ExactStepper stepper(s.tables, opt, z0, state0, 0, 0);
  REQUIRE(stepper.Run(1000, false));
  const Eigen::VectorXd c = ElasticPart(s.tables, stepper.state()),
                        d = ElasticPart(s.tables, cycle.Jump(z0, 1000));
  INFO("|stepped - jumped| " << (c - d).norm() << " of |state| "
                             << stepper.state().head(2 * s.tables.n).norm());
  // Stepping multiplies one propagator per segment where the map multiplies one per cycle: bound
  // k S eps |state| (measured 9.5e-14 = 0.9 k 4 eps |state|).
  CHECK((c - d).norm() <= 1000.0 * s.tables.segments() * std::numeric_limits<double>::epsilon() *
                              stepper.state().head(2 * s.tables.n).norm());
}

TEST_CASE("the contact certificate refuses a transient that can open the mesh", "[solver][fused]") {
  const Setup s(WhineSpec(), Tier::kTier1);
  auto [z0, state0] = StaticInitialState(s.tables);
  const ConstantContactCycle cycle(s.tables, ContactState::kDrive);
  const ContactCertificate calm = cycle.Certify(z0);
  CHECK(calm.certified);
  CHECK(calm.deviation_bound < calm.orbit_margin);
  // A large relative-speed kick: the gear flanks do separate when stepped.
  Eigen::VectorXd kicked = z0;
  kicked[s.tables.n] -= 100.0;  // pinion slowed by 100 rad/s: ~4.7 m/s along the line
  const ContactCertificate wild = cycle.Certify(kicked);
  CHECK_FALSE(wild.certified);
  CHECK_FALSE(wild.reason.empty());
  SolverOptions opt;
  opt.method = SolverMethod::kStepped;
  opt.cycles = 5;
  const SolverResult r = SimulateExact(s.tables, kicked, ContactState::kDrive, opt);
  CHECK(r.summary.separations > 0);  // the refusal was warranted
}

TEST_CASE("fused and stepped runs give the same trajectory", "[solver][fused]") {
  const Setup s(WhineSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions stepped, fused;
  stepped.method = SolverMethod::kStepped;
  fused.method = SolverMethod::kFused;
  stepped.cycles = fused.cycles = 100;
  stepped.transient_cycles = fused.transient_cycles = 300;
  const SolverResult a = SimulateExact(s.tables, z0, state0, stepped);
  const SolverResult b = SimulateExact(s.tables, z0, state0, fused);
  CHECK(b.summary.contact_certified);
  CHECK(b.summary.jumped_cycles == 300);
  CHECK(b.summary.fused_cycles == 100);
  CHECK(b.summary.matvec_per_cycle < 0.2 * a.summary.matvec_per_cycle);
  REQUIRE(a.trajectory.samples.size() == b.trajectory.samples.size());
  double diff = 0.0, scale = 0.0;
  for (size_t i = 0; i < a.trajectory.samples.size(); ++i) {
    CHECK(a.trajectory.samples[i].time == Approx(b.trajectory.samples[i].time).epsilon(1e-14));
    diff = std::max(diff, std::abs(a.trajectory.samples[i].te - b.trajectory.samples[i].te));
    scale = std::max(scale, std::abs(a.trajectory.samples[i].te));
  }
  // The stepped and fused runs round differently (per-segment V3 against one cycle-map product
  // per cycle with output rows): measured 1.2e-12 of the TE's size (0.9e-12 with one matvec per
  // segment), so 2e-12.
  CHECK(diff <= 2e-12 * scale);
}

// Recorded cycles of certified contact by output rows (cycle_output_rows.h) against the
// independent per-segment recording (one matvec per segment, chunk polynomials from the stepped
// states): samples, exact statistics and extrema.
TEST_CASE("recorded cycles by output rows match the per-segment recording", "[solver][fused]") {
  const Setup s(WhineSpec(), Tier::kTier3);
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions rows, pieces;
  rows.cycles = pieces.cycles = 400;
  rows.transient_cycles = pieces.transient_cycles = 50;
  rows.cycle_rows = true;
  pieces.cycle_rows = false;
  const SolverResult a = SimulateExact(s.tables, z0, state0, pieces);
  const SolverResult b = SimulateExact(s.tables, z0, state0, rows);
  REQUIRE(b.summary.contact_certified);
  CHECK(a.trajectory.statistics.row_cycles == 0);
  CHECK(b.trajectory.statistics.row_cycles == 400);
  CHECK(b.summary.matvecs < a.summary.matvecs / 10);  // one matvec per cycle, not per segment
  const auto& x = a.trajectory.samples;
  const auto& y = b.trajectory.samples;
  REQUIRE(x.size() == y.size());
  REQUIRE(x.size() == 400u * 32u);
  // Per output, the largest difference over its largest value. The two paths round differently
  // (one cycle-map product against the segment products; the state's rounding then moves through
  // the balanced Schur basis): measured 5e-12 (TE) to 3.5e-11 (pinion speed) on this model, so
  // 1e-10; the sample times are the same expression in both paths.
  std::array<double, 6> diff{}, size{};
  for (size_t i = 0; i < x.size(); ++i) {
    CHECK(x[i].time == y[i].time);
    CHECK(x[i].state == y[i].state);
    const std::array<double, 6> u = {x[i].te,           x[i].te_rate,     x[i].mesh_force,
                                     x[i].pinion_speed, x[i].wheel_speed, x[i].wheel_acceleration};
    const std::array<double, 6> v = {y[i].te,           y[i].te_rate,     y[i].mesh_force,
                                     y[i].pinion_speed, y[i].wheel_speed, y[i].wheel_acceleration};
    for (int o = 0; o < 6; ++o) {
      diff[o] = std::max(diff[o], std::abs(u[o] - v[o]));
      size[o] = std::max(size[o], std::abs(u[o]));
    }
  }
  for (int o = 0; o < 6; ++o) {
    INFO("output " << o << " relative difference " << diff[o] / size[o]);
    CHECK(diff[o] <= 1e-10 * size[o]);
  }
  const TrajectoryStatistics& p = a.trajectory.statistics;
  const TrajectoryStatistics& q = b.trajectory.statistics;
  CHECK(q.duration == p.duration);  // the same piece lengths, summed in the same order
  CHECK(q.pieces == p.pieces);
  CHECK(q.chunks == p.chunks);
  // Means and RMS from the closed-form integrals: relative to the output's RMS (a mean can be
  // near zero, the wheel acceleration's is).
  const double T = p.duration;
  const std::array<std::pair<const OutputStatistics*, const OutputStatistics*>, 3> stats = {
      {{&p.te, &q.te},
       {&p.mesh_force, &q.mesh_force},
       {&p.wheel_acceleration, &q.wheel_acceleration}}};
  for (const auto& [u, v] : stats) {
    const double rms = u->Rms(T);
    CHECK(std::abs(u->Mean(T) - v->Mean(T)) <= 1e-10 * (rms + std::abs(u->Mean(T))));
    CHECK(std::abs(u->Rms(T) - v->Rms(T)) <= 1e-10 * rms);
  }
  // Extrema: the same certified search on coefficients equal to rounding, so the same extremum
  // (to rounding of the TE's size) at the same time.
  CHECK(q.te.max == Approx(p.te.max).epsilon(1e-12));
  CHECK(q.te.min == Approx(p.te.min).epsilon(1e-12));
  CHECK(q.mesh_force.max == Approx(p.mesh_force.max).epsilon(1e-12));
  CHECK(q.te.time_of_max == Approx(p.te.time_of_max).epsilon(1e-12));
  CHECK(q.te.time_of_min == Approx(p.te.time_of_min).epsilon(1e-12));
  CHECK(q.mesh_force.time_of_max == Approx(p.mesh_force.time_of_max).epsilon(1e-12));
  // The end state: the cycle map advanced it, to rounding of the stepped one.
  CHECK((a.final_state - b.final_state).norm() <= 1e-11 * a.final_state.norm());
}

}  // namespace
}  // namespace gearnvh
