// Engine orders on any shaft, as accelerations or torques (issue 39 item 1, ExcitationOrder::kind
// and ::on): an order k of shaft s's own speed acts on s as T sin(k |W_s| t + phi),
// T = J_s a for an acceleration order. Against closed forms, the existing kind and CVODE.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;

constexpr int kRattlerInput = 0, kRattlerLayshaft = 1;

// The rattler (input g1 20 -> layshaft g2 30, g3 25 -> loose g4 on the input) with one order.
TrainSpec RattlerWithOrder(ExcitationKind kind, const std::string& on, double order,
                           double amplitude, double phase) {
  TrainSpec spec = testing::RattlerTrain(0.0);
  ExcitationOrder e;
  e.kind = kind;
  e.on = on;
  e.order = order;
  e.amplitude = amplitude;
  e.phase = phase;
  spec.operating.excitation = {e};
  return spec;
}

TEST_CASE("torque order: a torque T on the input is the acceleration order T / J_in",
          "[solver][train]") {
  // The existing kind applies J_in a on the input body: a torque order of T = J_in a is the same
  // input. Both runs from one static state over two mesh cycles of rattle: the TE agrees to
  // 1e-12 of its largest value (the inputs differ by rounding: (T / J) sin against a sin).
  const Model accel(RattlerWithOrder(ExcitationKind::kAcceleration, "", 2.0, 1500.0, 0.3));
  const double j_in = accel.tables.inertia[kRattlerInput];
  const Model torque(RattlerWithOrder(ExcitationKind::kTorque, "input", 2.0, 1500.0 * j_in, 0.3));
  REQUIRE(torque.tables.excitation.size() == 1);
  CHECK(torque.tables.excitation[0].order == accel.tables.excitation[0].order);
  const auto [z0, s0] = TrainStaticState(accel.tables);
  TrainStepper a(accel.tables, {}, z0, s0), b(torque.tables, {}, z0, s0);
  double worst = 0.0, scale = 0.0;
  for (int k = 1; k <= 64; ++k) {
    const double time = k * accel.tables.meshes[0].period / 32.0;
    REQUIRE(a.Run(time));
    REQUIRE(b.Run(time));
    for (int mesh = 0; mesh < 2; ++mesh) {
      scale = std::max(scale, std::abs(testing::MeshTe(accel.tables, a, mesh)));
      worst = std::max(worst, std::abs(testing::MeshTe(accel.tables, a, mesh) -
                                       testing::MeshTe(torque.tables, b, mesh)));
    }
  }
  REQUIRE(a.summary().events >= 2);
  CHECK(b.summary().events == a.summary().events);
  CHECK(worst <= 1e-12 * scale);
}

TEST_CASE("torque order: in free flight a shaft follows the closed form of its torque",
          "[solver][train]") {
  // Every mesh free at t = 0 and the bodies at rest: the layshaft (J, constant torque f from its
  // load) under T sin(w t + phi), w = k |W_lay| (an order of its own speed), obeys
  //   x(t) = f t^2 / 2J - (T / J w) [(sin(w t + phi) - sin phi) / w - t cos phi]
  // until the first impact, x in its own direction of rotation (it turns -z). The order as a
  // torque T, or as the acceleration a = T / J (J_s a on its shaft: the same input); at tier 1
  // and at tier 3, whose structure puts it on the layshaft's node as B^T d (its rotation is free
  // of the lateral DOF with the meshes free). Rounding of angles of ~1e-2 rad: 1e-14 rad.
  const double t_amp = 3.0, order = 2.0, phase = 0.7;
  const Model tier1(RattlerWithOrder(ExcitationKind::kTorque, "layshaft", order, t_amp, phase));
  const double j = tier1.tables.inertia[kRattlerLayshaft], f = tier1.tables.force[kRattlerLayshaft];
  const bool acceleration = GENERATE(false, true);
  const Tier tier = GENERATE(Tier::kTier1, Tier::kTier3);
  CAPTURE(acceleration, static_cast<int>(tier));
  const TrainSpec spec =
      acceleration
          ? RattlerWithOrder(ExcitationKind::kAcceleration, "layshaft", order, t_amp / j, phase)
          : RattlerWithOrder(ExcitationKind::kTorque, "layshaft", order, t_amp, phase);
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables t = BuildTrainTablesAtTier(spec, train, tier, {});
  const double w = order * std::abs(train.topology.bodies[kRattlerLayshaft].speed);
  // The exosystem turns at k |W_lay|: an order of the layshaft's own speed (2/3 of the input's).
  REQUIRE(t.excitation.size() == 1);
  CHECK(t.excitation[0].order * t.input_speed == Approx(w).epsilon(1e-15));
  Eigen::VectorXd z0 = Eigen::VectorXd::Zero(t.m);
  z0[t.constant_slot()] = 1.0;
  TrainStepper stepper(t, {}, z0, std::vector<ContactState>(2, ContactState::kFree));
  int checked = 0;
  double worst = 0.0, largest = 0.0;
  for (int k = 1; k <= 400; ++k) {
    const double time = 2e-6 * k;
    REQUIRE(stepper.Run(time));
    if (stepper.summary().events > 0) break;
    const double x =
        f * time * time / (2.0 * j) -
        t_amp / (j * w) *
            ((std::sin(w * time + phase) - std::sin(phase)) / w - time * std::cos(phase));
    const double angle = t.body_angles.row(kRattlerLayshaft).dot(stepper.state().head(t.n));
    worst = std::max(worst, std::abs(angle - x));
    largest = std::max(largest, std::abs(x));
    ++checked;
  }
  INFO(checked << " samples before the first impact; largest difference " << worst << " rad of "
               << largest << " rad");
  REQUIRE(checked >= 40);
  // A torque against the layshaft's rotation would miss by twice the order's part (~1e-3 rad).
  CHECK(worst <= 1e-14);
}

TEST_CASE("torque order: a rattle driven from the layshaft follows CVODE event by event",
          "[solver][train]") {
  // A torque order of the layshaft's speed on the layshaft: the stepper's exosystem against
  // CVODE's continuous torque (train_reference.h). Tolerance as the rattle test of
  // train_excitation_test.cc: 1e-8 of the TE over two mesh cycles.
  const Model s(RattlerWithOrder(ExcitationKind::kTorque, "layshaft", 3.0, 4.0, 0.2));
  testing::CheckRattleFollowsReference(
      testing::AgreeWithReference(s.tables, 2.0 * s.tables.meshes[0].period));
}

TEST_CASE("torque order: the rules name the order, its value and why", "[solver][train]") {
  const auto error_of = testing::ValidationError;
  CHECK(error_of(RattlerWithOrder(ExcitationKind::kTorque, "layshaft", 2.0, 3.0, 0.0)).first ==
        "accepted");
  const auto unknown = error_of(RattlerWithOrder(ExcitationKind::kTorque, "g1", 2.0, 3.0, 0.0));
  CHECK(unknown.first == "operating.excitation[0].on");
  CHECK_THAT(unknown.second, Catch::Contains("input, layshaft"));
  // A torque large enough to reverse the layshaft on its own: T / (J_lay k W) > W.
  const auto reversing =
      error_of(RattlerWithOrder(ExcitationKind::kTorque, "layshaft", 2.0, 1e5, 0.0));
  CHECK(reversing.first == "operating.excitation[0].amplitude");
  CHECK_THAT(reversing.second, Catch::Contains("'layshaft'"));
  // Order 2 of the layshaft and order 4/3 of the input share a frequency (2 x 2/3): refused when
  // they act on different shafts, summed when on the same one.
  TrainSpec both = RattlerWithOrder(ExcitationKind::kTorque, "layshaft", 2.0, 3.0, 0.0);
  ExcitationOrder on_input;
  on_input.order = 4.0 / 3.0;
  on_input.amplitude = 100.0;
  both.operating.excitation.push_back(on_input);
  CHECK(error_of(both).first == "operating.excitation[1].order");
  TrainSpec summed = RattlerWithOrder(ExcitationKind::kTorque, "layshaft", 2.0, 3.0, 0.0);
  summed.operating.excitation.push_back(summed.operating.excitation[0]);
  summed.operating.excitation[1].phase = std::numbers::pi;  // cancels the first
  REQUIRE(error_of(summed).first == "accepted");
  const Model cancelled(summed);
  REQUIRE(cancelled.tables.excitation.size() == 1);
  CHECK(cancelled.tables.excitation[0].amplitude <= 1e-15);
  // An axis (atlas, orbits) has one unit per parameter name: a torque order's amplitude is refused
  // there rather than shown in rad/s^2.
  TrainSpec axis = RattlerWithOrder(ExcitationKind::kTorque, "layshaft", 2.0, 3.0, 0.0);
  CHECK_THROWS_WITH(SetTrainParameter(axis, "operating.excitation[0].amplitude", 1.0, "--x"),
                    Catch::Contains("torque order"));
  axis.operating.excitation[0].kind = ExcitationKind::kAcceleration;
  SetTrainParameter(axis, "operating.excitation[0].amplitude", 1.0, "--x");
  CHECK(axis.operating.excitation[0].amplitude == 1.0);
}

}  // namespace
}  // namespace gearnvh
