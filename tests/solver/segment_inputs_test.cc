// The segment-mean inputs of the exact solver: the engine excitation's mean over a segment
// against an independent quadrature, and the precomputed-window path and the per-cycle phase path
// (one sincos per order and cycle) against the general one.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>

#include "gearnvh/model/quadrature.h"
#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"
#include "solver_fixture.h"

namespace gearnvh::testing {
namespace {

// (1/h) int_t0^{t0+h} sum_k a_k sin(w_k t + phi_k) dt by composite Gauss-Legendre (64 panels of
// 8 points: exact to rounding for the few periods a segment can hold), in the local time
// tau = t - t0 so that the panel widths are exact (t0 + tau rounds tau to ulp(t0), which for a
// segment 1e-6 of t0 skews the weights by ~1e-9).
double QuadratureMean(const SegmentTables& t, double t0, double h) {
  static const GaussLegendreRule rule = MakeGaussLegendre(8);
  double sum = 0.0;
  const int panels = 64;
  for (int p = 0; p < panels; ++p) {
    const double a = h * p / panels, b = h * (p + 1) / panels;
    sum += Integrate(rule, a, b, [&](double tau) {
      double v = 0.0;
      for (const ExcitationOrder& e : t.excitation) {
        const double w = e.order * t.pinion_speed;
        v += e.amplitude * std::sin((w * t0 + e.phase) + w * tau);
      }
      return v;
    });
  }
  return sum / h;
}

}  // namespace

TEST_CASE(
    "segment excitation mean: closed form against quadrature, windows against the general form",
    "[solver][inputs]") {
  GearboxSpec spec = IdleRattleSpec(1500.0);
  spec.operating.excitation = {{2.0, 1500.0, 0.3}, {15.5, 200000.0, -1.1}, {0.5, 40.0, 2.0}};
  const SolverSetup s(spec, Tier::kTier1);
  const SegmentTables& t = s.tables;
  REQUIRE(t.excitation_windows.size() == 3 * static_cast<size_t>(t.segments()));
  const double amplitude = 1500.0 + 200000.0 + 40.0;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(t.m);
  SegmentTables by_hand = t;  // the same tables without the precomputed windows
  by_hand.excitation_windows.clear();
  by_hand.excitation_midpoint_cos.clear();
  by_hand.excitation_midpoint_sin.clear();
  Eigen::VectorXd z_hand = z, z_phase = z;
  SegmentTables::CyclePhase phase;
  for (long cycle : {0L, 1L, 977L}) {
    for (int j = 0; j < t.segments(); ++j) {
      const double t0 = static_cast<double>(cycle) * t.mesh_period + t.boundaries[j];
      const double h = t.SegmentLength(j);
      // Quadrature of a smooth integrand to ~1e-16 relative; each phase w_k t is rounded to
      // ~|w_k t| eps in both forms, so they agree to 8 eps sum_k a_k (1 + |w_k t|).
      double tolerance = 0.0;
      for (const ExcitationOrder& e : t.excitation)
        tolerance += 8.0 * std::numeric_limits<double>::epsilon() * std::abs(e.amplitude) *
                     (1.0 + std::abs(e.order * t.pinion_speed * (t0 + h)));
      CHECK(std::abs(t.MeanExcitation(t0, h) - QuadratureMean(t, t0, h)) <= tolerance);
      // The window table and the general form are the same expression: equal to a few ulps.
      t.SetInputs(cycle, j, z);
      by_hand.SetInputs(cycle, j, z_hand);
      const int slot = t.input_slot(SegmentTables::kExcitationInput);
      CHECK(std::abs(z[slot] - z_hand[slot]) <= 1e-14 * amplitude);
      // sin(theta + psi) = sin theta cos psi + cos theta sin psi with theta the cycle's phase
      // and psi the midpoint's: against the quadrature, to the same rounding of the phases.
      t.SetInputs(cycle, j, z_phase, phase);
      CHECK(phase.cycle == cycle);
      CHECK(std::abs(z_phase[slot] - QuadratureMean(t, t0, h)) <= tolerance);
    }
  }
  // A very short window: the mean tends to the value at the midpoint (the difference-of-cosines
  // form lost ~8 digits here).
  const double mid = 0.123, h = 1e-12;
  double value = 0.0;
  for (const ExcitationOrder& e : t.excitation)
    value += e.amplitude * std::sin(e.order * t.pinion_speed * mid + e.phase);
  CHECK(std::abs(t.MeanExcitation(mid - 0.5 * h, h) - value) <= 1e-14 * amplitude);
}

TEST_CASE("the stepper's per-cycle excitation phases give the per-segment sine's events",
          "[solver][inputs]") {
  // The preprint's strong-rattle point on the flexible-shaft pair at tier 1 (7548.387097 rpm,
  // 20 N m, order 15.5 of 200000 rad/s^2): the stepper sets its inputs from the cycle's phases;
  // the same tables without the midpoint phases fall back to one sine per segment. The inputs
  // differ by rounding only, and over 24 cycles after a transient of 20 (~1 impact per cycle)
  // the events agree to the 1e-9 of a segment. Rattle grows rounding differences from
  // impact to impact, so the horizon is short (from cycle ~50 on they exceed 1e-9 of a segment).
  GearboxSpec spec = FlexibleShaftsPair();
  spec.operating.speed = 7548.387097 * std::numbers::pi / 30.0;
  spec.operating.torque = 20.0;
  spec.operating.excitation = {{15.5, 200000.0, 0.0}};
  const SolverSetup s(spec, Tier::kTier1);
  SegmentTables per_segment = s.tables;
  per_segment.excitation_midpoint_cos.clear();
  per_segment.excitation_midpoint_sin.clear();
  const auto [z0, state0] = StaticInitialState(s.tables);
  SolverOptions o;
  o.cycles = 24;
  o.transient_cycles = 20;
  const SolverResult a = SimulateExact(s.tables, z0, state0, o);
  const SolverResult b = SimulateExact(per_segment, z0, state0, o);
  REQUIRE(a.trajectory.events.size() >= 20);
  CheckSameEvents(a.trajectory, b.trajectory, 1e-9 * s.tables.SegmentLength(0));
}

}  // namespace gearnvh::testing
