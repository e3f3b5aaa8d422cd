// Drag on a body's speed, constant and viscous, absolute or relative to a shaft (issue 39 item 4,
// TrainLoad::viscous and ::relative_to): the torques it applies, the torque flow it sends, and
// the motion it gives, against closed forms.
#include <catch2/catch.hpp>
#include <cmath>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;

constexpr int kInput = 0, kLayshaft = 1, kLooseGear = 2;  // the rattler's bodies

// The rattler with g4's drag as a needle bearing's: T0 + c |dW| on its speed relative to the input
// shaft it idles on. g4 turns at 2/3 of the input's speed, the same way (20/30 then 25/25), so
// the drag pulls it forward and its reaction holds the input back.
TrainSpec NeedleBearingRattler(double viscous) {
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.operating.loads[1].viscous = viscous;
  spec.operating.loads[1].relative_to = "input";
  return spec;
}

TEST_CASE("drag: a loose gear's drag relative to its shaft is a torque pair and reverses its mesh",
          "[solver][train]") {
  const double c = 2e-3, t0 = testing::RattlerTrain(0.0).operating.loads[1].torque;
  const Model s(NeedleBearingRattler(c));
  const TrainTables& t = s.tables;
  const std::vector<TrainBody>& bodies = s.train.topology.bodies;
  const double relative = bodies[kLooseGear].speed - bodies[kInput].speed;
  REQUIRE(relative == Approx(-bodies[kInput].speed / 3.0).epsilon(1e-12));
  // Physical torques (about +z, the input's sense): on g4 -sgn(dW) (T0 + c |dW|); on the input
  // the reaction, opposite. Tables hold them in each body's own sense (all turn +z here).
  const double drag = t0 + c * std::abs(relative);
  CHECK(t.force[kLooseGear] == Approx(drag).epsilon(1e-14));
  CHECK(t.force[kInput] - s.train.input_torque == Approx(-drag).epsilon(1e-14));
  // Power balance: the input supplies the layshaft's load and the drag's loss T |dW|, nothing
  // else: sum_b f_b W_b = 0 with the input torque in f.
  double power = 0.0, scale = 0.0;
  for (size_t b = 0; b < bodies.size(); ++b) {
    power += t.force[static_cast<Eigen::Index>(b)] * std::abs(bodies[b].speed);
    scale += std::abs(t.force[static_cast<Eigen::Index>(b)] * bodies[b].speed);
  }
  CHECK(std::abs(power) <= 1e-14 * scale);
  CHECK(
      s.train.input_torque * bodies[kInput].speed ==
      Approx(20.0 * std::abs(bodies[kLayshaft].speed) + drag * std::abs(relative)).epsilon(1e-14));
  // g4, pulled forward, drives the layshaft: power flows from g4 (gear b) to g3 on the back flank
  // and the mesh carries the drag torque on g4.
  CHECK(s.train.meshes[1].back_flank_loaded);
  CHECK(s.train.meshes[1].transmitted_torque == Approx(drag).epsilon(1e-14));
  // g1-g2 carries the layshaft's load less what g4 sends back: on g2, (20 |W_lay| - D |W_g4|) /
  // |W_lay|, still on its drive flank.
  CHECK_FALSE(s.train.meshes[0].back_flank_loaded);
  CHECK(s.train.meshes[0].transmitted_torque == Approx((20.0 * std::abs(bodies[kLayshaft].speed) -
                                                        drag * std::abs(bodies[kLooseGear].speed)) /
                                                       std::abs(bodies[kLayshaft].speed))
                                                    .epsilon(1e-14));
  // The same rule without a direction: g4 at the input's own speed (g3 30 teeth, g4 20: 20/30 x
  // 30/20, one rounding from 1) has no constant drag relative to it, only a viscous one.
  TrainSpec level = NeedleBearingRattler(c);
  level.gears[2].gear.teeth = 30;
  level.gears[3].gear.teeth = 20;
  CHECK_THROWS_WITH(ValidateTrainSpec(level), Catch::Contains("has no direction"));
  level.operating.loads[1].torque = 0.0;
  CHECK_NOTHROW(ValidateTrainSpec(level));
  CHECK_FALSE(BuildTrainTables(level, BuildGearTrain(level)).free_rotation_damped);
  // The fluctuation: c (dw) on the relative speed, w = e_g4 - e_in.
  Eigen::VectorXd w = Eigen::VectorXd::Zero(t.n);
  w[kLooseGear] = 1.0;
  w[kInput] = -1.0;
  CHECK((t.structural_damping - c * w * w.transpose()).norm() <= 1e-15 * c);
  CHECK(t.free_rotation_damped);
  CHECK(t.neutral_directions() == 1);
  // A drag beyond the tooth-load limit on the mesh that only g4's drag loads: named at its viscous
  // part, which is most of it (1000 x 28 N m against 0.05 N m).
  try {
    ValidateTrainSpec(NeedleBearingRattler(1000.0));
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "operating.loads[1].viscous");
    CHECK_THAT(e.rule(), Catch::Contains("tooth load"));
  }
}

TEST_CASE("drag: bodies in free flight under a viscous drag follow the closed-form exponential",
          "[solver][train]") {
  // Every mesh free at t = 0 and no excitation: M x'' = f - c w (w^T x'). The relative speed
  // u = w^T x' obeys u' = a - sigma u (a = w^T M^-1 f, sigma = c w^T M^-1 w), so
  //   u(t) = u_inf + (u_0 - u_inf) e^(-sigma t),  u_inf = a / sigma,
  //   x(t) = x_0 + x'_0 t + M^-1 f t^2 / 2 - c M^-1 w [u_inf t^2 / 2 + (u_0 - u_inf)
  //          (t - (1 - e^(-sigma t)) / sigma) / sigma],
  // until the first impact. c is chosen so that sigma t is about 1 within the flight.
  const Model probe(NeedleBearingRattler(1e-3));
  const Eigen::VectorXd& j = probe.tables.inertia;
  const double sigma = 4000.0;  // 1/s
  const double c = sigma / (1.0 / j[kLooseGear] + 1.0 / j[kInput]);
  const Model s(NeedleBearingRattler(c));
  const TrainTables& t = s.tables;
  const int n = t.n;
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  w[kLooseGear] = 1.0;
  w[kInput] = -1.0;
  const Eigen::VectorXd acc = t.force.cwiseQuotient(t.inertia);
  const Eigen::VectorXd winv = w.cwiseQuotient(t.inertia);
  REQUIRE(c * w.dot(winv) == Approx(sigma).epsilon(1e-12));
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(t.m);
  z0[t.constant_slot()] = 1.0;
  z0[n + kLooseGear] = 0.5;  // rad/s: a relative speed u_0 of its own
  const double u0 = 0.5, u_inf = w.dot(acc) / sigma;
  const auto x_at = [&](double time) -> Eigen::VectorXd {
    const double decay = -std::expm1(-sigma * time);  // 1 - e^(-sigma t), accurate for small t
    const double integral =
        u_inf * time * time / 2.0 + (u0 - u_inf) * (time - decay / sigma) / sigma;
    return z0.segment(n, n) * time + acc * time * time / 2.0 - c * winv * integral;
  };
  TrainStepper stepper(t, {}, z0, std::vector<ContactState>(2, ContactState::kFree));
  int checked = 0;
  double worst = 0.0, largest = 0.0;
  for (int k = 1; k <= 200; ++k) {
    const double time = 5e-6 * k;
    REQUIRE(stepper.Run(time));
    if (stepper.summary().events > 0) break;  // the first impact ends the closed form
    const Eigen::VectorXd x = x_at(time);
    worst = std::max(worst, (stepper.state().head(n) - x).cwiseAbs().maxCoeff());
    largest = std::max(largest, x.cwiseAbs().maxCoeff());
    ++checked;
  }
  INFO(checked << " samples before the first impact; largest difference " << worst
               << " rad of angles up to " << largest << " rad; sigma t up to "
               << sigma * 5e-6 * checked);
  REQUIRE(checked >= 40);  // sigma t reaches 0.8 at least
  // The exact exponential against the closed form: rounding of angles of ~1e-3 rad (the
  // generator's eigenvalues 0 and -sigma, a decomposition to ~1e-13 relative): 1e-14 rad. Without
  // the drag's fluctuation the angles differ by c w u t^2 / 2 J, ~1e-5 rad here.
  CHECK(worst <= 1e-14);
}

// The two-stage reducer in permanent contact with a viscous drag on its output's absolute speed.
TrainSpec ChurningReducer(double viscous) {
  TrainSpec spec = testing::TwoStageTrain(150.0, 0.0, 600.0);
  spec.operating.excitation.clear();
  spec.operating.loads[0].viscous = viscous;
  return spec;
}

TEST_CASE("drag: a viscous drag damps the free rotation at the rigid train's rate",
          "[solver][train]") {
  // The train turned faster as one body, by q along its free rotation r (M-normalised): the drag
  // resists with c r_out q, so q decays at
  //   sigma = c r_out^2 = c W_out^2 / sum_b J_b W_b^2  (the output's speed squared over the
  // train's inertia reduced to it), while the meshes take no part (v_i^T r = 0). Tier 1 and tier 3
  // (the structure: the drag at the output's node) alike.
  const double c = 0.5;  // N m s/rad
  const TrainSpec spec = ChurningReducer(c);
  const GearTrain train = BuildGearTrain(spec);
  const std::vector<TrainBody>& bodies = train.topology.bodies;
  double reduced_inertia = 0.0;
  for (size_t b = 0; b < bodies.size(); ++b) {
    reduced_inertia += train.body_inertia[b] * bodies[b].speed * bodies[b].speed;
  }
  const double sigma = c * bodies[2].speed * bodies[2].speed / reduced_inertia;
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  CAPTURE(static_cast<int>(tier));
  const TrainTables t = BuildTrainTablesAtTier(spec, train, tier, {});
  REQUIRE(t.free_rotation_damped);
  REQUIRE(t.neutral_directions() == 1);
  auto [z0, s0] = TrainStaticState(t);
  const double q0 = 1.0;  // the input 20 rad/s faster, in M-normalised units (linear: any size)
  z0.segment(t.n, t.n) += q0 * t.rigid_rotation;
  TrainStepper stepper(t, {}, z0, s0);
  const double period = t.meshes[0].period;
  double worst = 0.0;
  for (int k = 1; k <= 40; ++k) {
    const double time = 5.0 * k * period;
    REQUIRE(stepper.Run(time));
    const double q = t.recenter_row.dot(stepper.state().segment(t.n, t.n));
    worst = std::max(worst, std::abs(q - q0 * std::exp(-sigma * time)));
  }
  INFO("sigma " << sigma << " 1/s over " << 200 * period << " s; largest difference " << worst);
  REQUIRE(sigma * 200 * period > 5.0);  // it decays to under 1 %
  REQUIRE(stepper.summary().events == 0);
  // Exactly, q' = -c r_out (q r_out + p'), p the output's vibration angle (zero-mean, from the
  // mesh stiffness's variation, ~2.5e-5 rad at tier 1, more with the lateral modes of tier 3): q
  // differs from q0 e^(-sigma t) by about c r_out p, independent of q0 (measured 1.8e-4 at tier 1,
  // 4.3e-4 at tier 3). An undamped q misses by 0.99 q0, a drag at half or twice its rate by
  // 0.25 q0.
  CHECK(worst <= 2e-3 * q0);
}

TEST_CASE("drag: the train's momentum along the free rotation balances the drag's impulse",
          "[solver][train]") {
  // r^T M x'' = r^T f + r^T F_mesh - r^T C x' with r^T f = 0 (the input balances every mean load),
  // r^T F_mesh = 0 (v_i^T r = 0) and C = c w w^T (w = e_out): q + c r_out x_out is conserved to
  // rounding whatever the meshes do. Within the first common period (before the stepper recentres
  // the angles), at tier 1.
  const double c = 0.5;
  const Model s(ChurningReducer(c));
  const TrainTables& t = s.tables;
  auto [z0, s0] = TrainStaticState(t);
  z0.segment(t.n, t.n) += 0.1 * t.rigid_rotation;
  z0[t.n + 2] += 3.0;  // and the output shaken: 3 rad/s of its own
  const double r_out = t.rigid_rotation[2];
  const auto momentum = [&](const Eigen::VectorXd& z) {
    return t.recenter_row.dot(z.segment(t.n, t.n)) + c * r_out * z[2];
  };
  const double p0 = momentum(z0);
  TrainStepper stepper(t, {}, z0, s0);
  double worst = 0.0, moved = 0.0;
  for (int k = 1; k <= 50; ++k) {
    REQUIRE(stepper.Run(k * 0.018 * t.common_period));
    worst = std::max(worst, std::abs(momentum(stepper.state()) - p0));
    moved = std::max(moved, std::abs(t.recenter_row.dot(stepper.state().segment(t.n, t.n)) -
                                     t.recenter_row.dot(z0.segment(t.n, t.n))));
  }
  REQUIRE(stepper.summary().recenterings == 0);
  INFO("momentum drift " << worst << " of " << p0 << "; q moved by " << moved);
  REQUIRE(moved > 1e-3);  // the drag's impulse moved q
  // Rounding of a state of ~1e-1 over ~400 exact pieces: 1e-12.
  CHECK(worst <= 1e-12);
}

TEST_CASE("drag: a rattling train with a needle-bearing drag follows CVODE event by event",
          "[solver][train]") {
  // The rattler under engine order 2 (1500 rad/s^2) with g4's drag on its speed relative to the
  // input shaft, viscous part c = 2e-3 N m s/rad (its damper joins g4 and the input in every
  // generator). Over two mesh cycles, tolerance as the rattle test of train_excitation_test.cc:
  // 1e-8 of the TE (CVODE at rtol 1e-13 through a few impacts).
  TrainSpec spec = NeedleBearingRattler(2e-3);
  spec.operating.excitation = {{2.0, 1500.0, 0.0}};
  const Model s(spec);
  testing::CheckRattleFollowsReference(
      testing::AgreeWithReference(s.tables, 2.0 * s.tables.meshes[0].period));
}

TEST_CASE("drag: certified jumps carry the damped rotation's speed", "[solver][train]") {
  // The loaded reducer in permanent contact under engine order 2 with a viscous drag on its output:
  // the order drives the free rotation's speed, which the drag damps, so the period map keeps that
  // speed as a coordinate (only its angle is projected out). Jumped and stepped runs record the
  // same orbit: TE RMS to 1e-10 of the TE p-p as the reducer's own jump test, and the rotation's
  // speed at the end to 1e-9 of its swing.
  TrainSpec spec = testing::TwoStageTrain(300.0, 100.0, 300.0);
  spec.operating.loads[0].viscous = 0.5;
  const Model s(spec);
  const TrainTables& t = s.tables;
  REQUIRE(t.free_rotation_damped);
  const auto [stepped, jumped] = testing::CheckJumpsMatchStepping(t);
  const auto speed = [&](const Eigen::VectorXd& z) {
    return t.recenter_row.dot(z.segment(t.n, t.n));
  };
  INFO("rotation speed at the end: stepped " << speed(stepped.state) << ", jumped "
                                             << speed(jumped.state));
  REQUIRE(std::abs(speed(stepped.state)) > 1e-6);  // the order moves it
  CHECK(std::abs(speed(jumped.state) - speed(stepped.state)) <=
        1e-9 * std::abs(speed(stepped.state)));
}

TEST_CASE("drag: every tier applies it to the bodies' angles as tier 1 does", "[solver][train]") {
  // Counter-rotating shafts: the layshaft's drag relative to the input (dW = -1.5 W_in), whose
  // w = (s_lay e_lay - s_in e_in) has entries of one sign (-1, -1) in the bodies' own senses.
  // With the meshes fixed (one GearTrain for both), the drag adds to the tier-1 force f and
  // damping C deltas df, dC; a reduced tier whose body angles are th = B x (B =
  // TrainTables::body_angles) must add B^T df and B^T dC B (virtual work). Tolerance: the
  // reduction's rounding, 1e-10 of the largest entry.
  TrainSpec plain = testing::TwoStageTrain(150.0, 0.0, 600.0);
  plain.operating.excitation.clear();
  const GearTrain train = BuildGearTrain(plain);
  TrainSpec dragged = plain;
  dragged.operating.loads.push_back({"layshaft", 0.5});
  dragged.operating.loads.back().viscous = 0.02;
  dragged.operating.loads.back().relative_to = "input";
  const TrainTables one = BuildTrainTables(plain, train),
                    one_drag = BuildTrainTables(dragged, train);
  const Eigen::VectorXd df = one_drag.force - one.force;
  const Eigen::MatrixXd dc = one_drag.structural_damping;
  Eigen::Vector3d w(-1.0, -1.0, 0.0);  // input (+z), layshaft (-z): w = s_lay e_lay - s_in e_in
  CHECK((dc - 0.02 * w * w.transpose()).norm() <= 1e-15);
  CHECK(df[0] == Approx(-(0.5 + 0.02 * 1.5 * plain.operating.speed)).epsilon(1e-12));
  // Both resist by T + c |dW|; differences of forces of ~100 N m: 1e-12 relative.
  CHECK(df[1] == Approx(df[0]).epsilon(1e-12));
  const TrainTables three = BuildTrainTablesAtTier(plain, train, Tier::kTier3, {});
  const TrainTables three_drag = BuildTrainTablesAtTier(dragged, train, Tier::kTier3, {});
  REQUIRE(three.n == three_drag.n);
  const Eigen::MatrixXd& b = three.body_angles;
  REQUIRE(b.rows() == 3);
  const Eigen::VectorXd df3 = three_drag.force - three.force;
  const Eigen::MatrixXd dc3 = three_drag.structural_damping - three.structural_damping;
  INFO("force: " << (df3 - b.transpose() * df).norm() << " of " << df3.norm()
                 << "; damping: " << (dc3 - b.transpose() * dc * b).norm() << " of " << dc3.norm());
  REQUIRE(dc3.norm() > 0.0);
  CHECK((df3 - b.transpose() * df).norm() <= 1e-10 * df3.norm());
  CHECK((dc3 - b.transpose() * dc * b).norm() <= 1e-10 * dc3.norm());
  CHECK(three_drag.free_rotation_damped);
}

}  // namespace
}  // namespace gearnvh
