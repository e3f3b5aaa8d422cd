// The inputs of the exact solver: the engine orders' states at each segment's start, from the
// per-cycle phase path (one sincos per order and cycle, angle sums per segment) against the direct
// sine and cosine, and the stepper's events with either.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>

#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"
#include "solver_fixture.h"

namespace gearnvh::testing {

TEST_CASE("the orders' states at a segment's start: per-cycle phases against sin and cos",
          "[solver][inputs]") {
  GearboxSpec spec = IdleRattleSpec(1500.0);
  spec.operating.excitation = {{2.0, 1500.0, 0.3}, {15.5, 200000.0, -1.1}, {0.5, 40.0, 2.0}};
  const SolverSetup s(spec, Tier::kTier1);
  const SegmentTables& t = s.tables;
  REQUIRE(t.inputs == 6);
  REQUIRE(t.excitation_start_cos.size() == 3 * static_cast<size_t>(t.segments()));
  Eigen::VectorXd z = Eigen::VectorXd::Zero(t.m), z_phase = z;
  SegmentTables::CyclePhase phase = t.MakeCyclePhase();
  for (long cycle : {0L, 1L, 977L}) {
    for (int j = 0; j < t.segments(); ++j) {
      const double t0 = static_cast<double>(cycle) * t.mesh_period + t.boundaries[j];
      t.SetInputs(cycle, j, z);
      t.SetInputs(cycle, j, z_phase, phase);
      for (size_t k = 0; k < t.excitation.size(); ++k) {
        const ExcitationOrder& e = t.excitation[k];
        const double angle = e.order * t.pinion_speed * t0 + e.phase;
        const int slot = t.input_slot(SegmentTables::ExcitationInput(static_cast<int>(k)));
        // sin(theta + psi) = sin theta cos psi + cos theta sin psi with theta the cycle's phase
        // and psi the segment start's: the phases are rounded to ~|w t| eps in both forms, so they
        // agree to 8 eps a (1 + |w t|).
        const double tolerance = 8.0 * std::numeric_limits<double>::epsilon() * e.amplitude *
                                 (1.0 + std::abs(e.order * t.pinion_speed * t0));
        CHECK(std::abs(z[slot] - e.amplitude * std::sin(angle)) <= tolerance);
        CHECK(std::abs(z[slot + 1] - e.amplitude * std::cos(angle)) <= tolerance);
        CHECK(std::abs(z_phase[slot] - z[slot]) <= tolerance);
        CHECK(std::abs(z_phase[slot + 1] - z[slot + 1]) <= tolerance);
      }
    }
  }
}

TEST_CASE("the stepper's per-cycle excitation phases give the per-segment sine's events",
          "[solver][inputs]") {
  // The preprint's strong-rattle point on the flexible-shaft pair at tier 1 (7548.387097 rpm,
  // 20 N m, order 15.5 of 200000 rad/s^2): the stepper sets its inputs from the cycle's phases;
  // the same tables without the start phases fall back to a sine and cosine per segment. The inputs
  // differ by rounding only, and over 24 cycles after a transient of 20 (~1 impact per cycle)
  // the events agree to the 1e-9 of a segment. Rattle grows rounding differences from
  // impact to impact, so the horizon is short (from cycle ~50 on they exceed 1e-9 of a segment).
  GearboxSpec spec = FlexibleShaftsPair();
  spec.operating.speed = 7548.387097 * std::numbers::pi / 30.0;
  spec.operating.torque = 20.0;
  spec.operating.excitation = {{15.5, 200000.0, 0.0}};
  const SolverSetup s(spec, Tier::kTier1);
  SegmentTables per_segment = s.tables;
  per_segment.excitation_start_cos.clear();
  per_segment.excitation_start_sin.clear();
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
