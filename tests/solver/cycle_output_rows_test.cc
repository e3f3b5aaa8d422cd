// Recorded cycles of certified contact by output rows (cycle_output_rows.h) against the
// piece-by-piece recording of the same run (one matvec per segment, chunk polynomials from the
// stepped states), sample by sample and statistic by statistic, from the starts that matter: a
// static equilibrium with no transient (the run enters the rows in cycle 0, off its orbit), the
// orbit after a transient, and with an engine excitation order.
#include "gearnvh/solver/cycle_output_rows.h"

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"
#include "solver/solver_fixture.h"

namespace gearnvh {
namespace {

using testing::kRpm;

// The loaded 20:30 pair at 60 rpm of tests/nvh/manufacturing_errors_test.cc: its mesh modes decay
// by ~1e-30 per mesh cycle, so their eigenvalues are rounding (the case that exposed the dropped
// tail in the first row cycle).
GearboxSpec QuasiStaticPair() {
  GearboxSpec spec = testing::StandardPair(20, 30, 3e-3, 20e-3);
  spec.operating.speed = 60.0 * kRpm;
  spec.operating.torque = 100.0;
  return spec;
}

// The loaded industrial pair of examples/industrial_whine.yaml (permanent contact).
GearboxSpec IndustrialWhineSpec() {
  GearboxSpec s = testing::StandardPair(25, 75, 4e-3, 40e-3);
  s.pinion.bore_diameter = 45e-3;
  s.wheel.bore_diameter = 80e-3;
  s.pinion.tip_relief = s.wheel.tip_relief = TipRelief{20e-6, 8e-3};
  s.mesh.backlash = 150e-6;
  s.mesh.damping_ratio = 0.07;
  s.mesh.friction_coefficient = 0.04;
  s.operating.speed = 1500 * kRpm;
  s.operating.torque = 1500;
  return s;
}

struct Start {
  Eigen::VectorXd z;
  ContactState state;
};

// Runs `cycles` recorded cycles after `transient` ones with output rows on and off and compares.
// Returns the number of row cycles of the rows run.
long CompareRecordings(const SegmentTables& tables, const Start& start, long transient,
                       long cycles) {
  SolverOptions rows, pieces;
  rows.cycles = pieces.cycles = cycles;
  rows.transient_cycles = pieces.transient_cycles = transient;
  rows.cycle_rows = true;
  pieces.cycle_rows = false;
  const SolverResult a = SimulateExact(tables, start.z, start.state, pieces);
  const SolverResult b = SimulateExact(tables, start.z, start.state, rows);
  CHECK(a.trajectory.statistics.row_cycles == 0);
  CHECK(a.summary.contact_certified == b.summary.contact_certified);
  const auto& x = a.trajectory.samples;
  const auto& y = b.trajectory.samples;
  REQUIRE(x.size() == y.size());
  REQUIRE(x.size() == static_cast<size_t>(cycles * rows.samples_per_cycle));
  // Tolerance 1e-10 of each output's largest value: both recordings are exact maps of the same
  // state (chunk polynomials of the stepped state against rows on the cycle's start state through
  // the cycle map and its Schur basis), so they differ only by rounding, amplified by the norms
  // of the cycle map and the basis change (measured over these cases: TE 1.3e-13, force 7e-13,
  // speeds 9e-12, TE rate 1.6e-11; cycle_map_test.cc's 400-cycle run 3.5e-11). The two bugs this
  // caught were far above it: a tail of modes dropped in the first row cycle (1.7e-3 of the TE)
  // and the constant slot drifting by 8e-13 per cycle (1.4e-10 of the wheel acceleration after
  // 30 cycles, growing without bound).
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
    if (i < static_cast<size_t>(rows.samples_per_cycle)) {
      INFO("first cycle, sample " << i << ": TE " << u[0] << " against " << v[0]);
      CHECK(std::abs(u[0] - v[0]) <= 1e-10 * size[0]);
    }
  }
  for (int o = 0; o < 6; ++o) {
    INFO("output " << o << " relative difference " << diff[o] / size[o]);
    CHECK(diff[o] <= 1e-10 * size[o]);
  }
  const TrajectoryStatistics& p = a.trajectory.statistics;
  const TrajectoryStatistics& q = b.trajectory.statistics;
  CHECK(q.duration == p.duration);
  CHECK(q.pieces == p.pieces);
  CHECK(q.chunks == p.chunks);
  // TE and mesh force mean and RMS, and the rattle index (the wheel acceleration's RMS about its
  // mean), from the closed-form integrals: relative to the output's RMS plus |mean| (the wheel
  // acceleration's mean is near zero), same 1e-10.
  const double T = p.duration;
  const std::array<std::pair<const OutputStatistics*, const OutputStatistics*>, 3> stats = {
      {{&p.te, &q.te},
       {&p.mesh_force, &q.mesh_force},
       {&p.wheel_acceleration, &q.wheel_acceleration}}};
  for (const auto& [u, v] : stats) {
    const double scale = u->Rms(T) + std::abs(u->Mean(T));
    CHECK(std::abs(u->Mean(T) - v->Mean(T)) <= 1e-10 * scale);
    CHECK(std::abs(u->Rms(T) - v->Rms(T)) <= 1e-10 * scale);
  }
  // Peak to peak and the peak force: the same certified extremum search on coefficients equal to
  // rounding.
  const double te_scale = std::max(std::abs(p.te.max), std::abs(p.te.min));
  CHECK(std::abs((q.te.max - q.te.min) - (p.te.max - p.te.min)) <= 1e-10 * te_scale);
  CHECK(q.mesh_force.max == Approx(p.mesh_force.max).epsilon(1e-10));
  CHECK((a.final_state - b.final_state).norm() <= 1e-10 * a.final_state.norm());
  return q.row_cycles;
}

TEST_CASE("output rows from a static equilibrium with no transient match the pieces",
          "[solver][fused][rows]") {
  for (Tier tier : {Tier::kTier1, Tier::kTier3}) {
    INFO(TierName(tier));
    const testing::SolverSetup s(QuasiStaticPair(), tier);
    const Start start{DriveEquilibrium(s.tables), ContactState::kDrive};
    // Certified at the start (tier 1 in the release build) or after the first cycle (tier 3,
    // whose flexible modes ring from the static start, and tier 1 under the sanitizer build's
    // rounding): the rows start off the orbit, with every mode excited.
    CHECK(CompareRecordings(s.tables, start, 0, 30) >= 29);
  }
  const testing::SolverSetup whine(IndustrialWhineSpec(), Tier::kTier1);
  const auto [z0, state0] = StaticInitialState(whine.tables);
  CHECK(CompareRecordings(whine.tables, {z0, state0}, 0, 30) > 0);
}

TEST_CASE("output rows on the orbit after a transient match the pieces", "[solver][fused][rows]") {
  for (Tier tier : {Tier::kTier1, Tier::kTier3}) {
    INFO(TierName(tier));
    const testing::SolverSetup s(IndustrialWhineSpec(), tier);
    const auto [z0, state0] = StaticInitialState(s.tables);
    CHECK(CompareRecordings(s.tables, {z0, state0}, 60, 30) == 30);
  }
}

TEST_CASE("with an engine excitation order the rows do not apply and the recording is unchanged",
          "[solver][fused][rows]") {
  // Excitation makes one mesh cycle's map differ from the next's: the cycle map is never built
  // (SimulateExact fuses only without excitation), so rows on and off are the same run.
  for (Tier tier : {Tier::kTier1, Tier::kTier3}) {
    INFO(TierName(tier));
    GearboxSpec spec = IndustrialWhineSpec();
    spec.operating.excitation = {{3.0, 50.0, 0.3}};
    const testing::SolverSetup s(spec, tier);
    const auto [z0, state0] = StaticInitialState(s.tables);
    CHECK(CompareRecordings(s.tables, {z0, state0}, 10, 20) == 0);
  }
}

}  // namespace
}  // namespace gearnvh
