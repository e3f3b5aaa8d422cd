// Multi-stage couplings (issue 39 item 2, TrainCoupling::stages): the piecewise-linear curve, the
// static twist, stage changes as exact events (energy conserved across them, CVODE event by event)
// and the coupling torque's exact statistics, against closed forms.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;
constexpr double kDeg = std::numbers::pi / 180.0;

// A clutch damper's three stages: k1 to a1, k2 to a2, k3 beyond.
TrainCoupling ThreeStages(double k1, double a1, double k2, double a2, double k3) {
  TrainCoupling c;
  c.name = "clutch_damper";
  c.shaft_a = "flywheel";
  c.shaft_b = "input";
  c.stiffness = k1;
  c.stages = {{a1, k2}, {a2, k3}};
  return c;
}

// Flywheel -(staged clutch damper)- input (g1, 20) -> output (g2, 30) -(halfshaft)- wheels under a
// road load; constant mesh stiffness (no error, no variation), every damping `damping`.
TrainSpec StagedDriveline(const TrainCoupling& clutch, double load, double damping) {
  TrainSpec t;
  t.name = "staged driveline";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("flywheel", 0.12), testing::RigidShaft("input", 2e-3),
              testing::RigidShaft("output", 3e-3), testing::RigidShaft("wheels", 8.0)};
  t.gears = {testing::TrainGearOf("g1", "input", 20), testing::TrainGearOf("g2", "output", 30)};
  t.meshes = {testing::TrainMeshOf("g1", "g2")};
  t.meshes[0].mesh.stiffness = FourierStiffness{3e8, {}, {}};
  t.meshes[0].mesh.damping_ratio = damping > 0.0 ? 0.05 : 0.0;
  TrainCoupling halfshaft;
  halfshaft.name = "halfshaft";
  halfshaft.shaft_a = "output";
  halfshaft.shaft_b = "wheels";
  halfshaft.stiffness = 12000.0;
  halfshaft.damping = damping;
  TrainCoupling staged = clutch;
  staged.damping = damping;
  t.couplings = {staged, halfshaft};
  t.operating.input_shaft = "flywheel";
  t.operating.speed = 800.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"wheels", load}};
  t.analysis.segments_per_cycle = 8;
  return t;
}

TEST_CASE("coupling stages: the curve, its inverse and its slope are the closed form",
          "[model][train]") {
  const TrainCoupling c = ThreeStages(20.0, 2.0 * kDeg, 500.0, 6.0 * kDeg, 3000.0);
  const CouplingSprings s = c.springs();
  // Hand-written values of the piecewise line (exact arithmetic up to rounding: 1e-14).
  const double at_a1 = 20.0 * 2.0 * kDeg, at_a2 = at_a1 + 500.0 * 4.0 * kDeg;
  CHECK(s.Torque(1.0 * kDeg) == Approx(20.0 * kDeg).epsilon(1e-14));
  CHECK(s.Torque(2.0 * kDeg) == Approx(at_a1).epsilon(1e-14));
  CHECK(s.Torque(4.0 * kDeg) == Approx(at_a1 + 500.0 * 2.0 * kDeg).epsilon(1e-14));
  CHECK(s.Torque(8.0 * kDeg) == Approx(at_a2 + 3000.0 * 2.0 * kDeg).epsilon(1e-14));
  for (double twist : {0.5, 1.9, 2.1, 5.0, 6.5, 20.0}) {
    CHECK(s.Torque(-twist * kDeg) == -s.Torque(twist * kDeg));  // odd
    // The inverse returns the twist: 1e-13 (two roundings per stage).
    CHECK(s.StaticTwist(s.Torque(twist * kDeg)) == Approx(twist * kDeg).epsilon(1e-13));
    CHECK(s.StaticTwist(-s.Torque(twist * kDeg)) == Approx(-twist * kDeg).epsilon(1e-13));
  }
  CHECK(s.TangentStiffness(1.0 * kDeg) == 20.0);
  CHECK(s.TangentStiffness(-3.0 * kDeg) == 500.0);
  CHECK(s.TangentStiffness(7.0 * kDeg) == 3000.0);
}

TEST_CASE("coupling stages: the rules name the stage, its value and why", "[model][train]") {
  const auto refused = [](const TrainCoupling& c, const std::string& path) {
    const auto [where, rule] = testing::ValidationError(StagedDriveline(c, 30.0, 0.1));
    INFO(rule);
    CHECK(where == path);
  };
  refused(ThreeStages(20.0, 2.0 * kDeg, 10.0, 6.0 * kDeg, 3000.0),
          "couplings.clutch_damper.stages[1].stiffness");  // softer than the stage before
  refused(ThreeStages(20.0, 2.0 * kDeg, 500.0, 1.0 * kDeg, 3000.0),
          "couplings.clutch_damper.stages[1].to");  // ends before the stage before
  refused(ThreeStages(20.0, 0.0, 500.0, 6.0 * kDeg, 3000.0),
          "couplings.clutch_damper.stages[0].to");
  refused(ThreeStages(20.0, 2.0 * kDeg, 500.0, 100.0 * kDeg, 3000.0),
          "couplings.clutch_damper.stages[1].to");  // past 90 deg
  refused(ThreeStages(0.0, 2.0 * kDeg, 500.0, 6.0 * kDeg, 3000.0),
          "couplings.clutch_damper.stages[0].stiffness");
  CHECK(testing::ValidationError(
            StagedDriveline(ThreeStages(20.0, 2.0 * kDeg, 500.0, 6.0 * kDeg, 3000.0), 30.0, 0.1))
            .first == "accepted");
}

TEST_CASE("coupling stages: the static state twists the coupling along its stages",
          "[solver][train]") {
  // 20 N m through the clutch (30 N m on the wheels through 20:30): past stage 1's 0.698 N m at 2
  // deg, in stage 2 at 2 deg + (20 - 0.698) / 500 rad = 4.21 deg.
  const TrainCoupling clutch = ThreeStages(20.0, 2.0 * kDeg, 500.0, 6.0 * kDeg, 3000.0);
  const Model s(StagedDriveline(clutch, 30.0, 0.1));
  const TrainTables& t = s.tables;
  REQUIRE(t.gear_meshes == 1);
  REQUIRE(t.meshes.size() == 3);
  CHECK(t.meshes[1].name == "clutch_damper stage 2");
  CHECK(t.meshes[2].stage == 3);
  const double expected = 2.0 * kDeg + (20.0 - 20.0 * 2.0 * kDeg) / 500.0;
  CHECK(s.train.couplings[0].MeanTwist() == Approx(expected).epsilon(1e-14));
  const auto [z0, states] = TrainStaticState(t);
  const double twist = z0[0] - z0[1];  // flywheel - input, tier 1's own coordinates
  // A static solve of a 4 x 4 system with stiffnesses 20 ... 3e8 r^2: 1e-9 relative.
  CHECK(twist == Approx(expected).epsilon(1e-9));
  CHECK(states[0] == ContactState::kDrive);
  CHECK(states[1] == ContactState::kDrive);  // stage 2 engaged
  CHECK(states[2] == ContactState::kFree);   // stage 3 not reached
  CHECK(LoadedContactStates(t) ==
        std::vector<ContactState>{ContactState::kDrive, ContactState::kDrive, ContactState::kFree});
  // Reversed power (the wheels drive): the same twist with the other sign, stage 2 on its back
  // wall.
  TrainSpec reversed = StagedDriveline(clutch, 30.0, 0.1);
  std::swap(reversed.couplings[0].shaft_a, reversed.couplings[0].shaft_b);
  const Model r(reversed);
  const auto [zr, sr] = TrainStaticState(r.tables);
  CHECK(zr[1] - zr[0] == Approx(-expected).epsilon(1e-9));
  CHECK(sr[1] == ContactState::kBack);
}

TEST_CASE("coupling stages: at tier 3 a stage acts on the twist and the static twist is tier 1's",
          "[solver][train]") {
  // The stage's row is the two shafts' angle rows' difference (to rounding, 1e-12 of the row), and
  // the coupling's static twist is statically determinate: the structure's lateral compliance
  // does not change it (1e-8: a static solve of the reduced model).
  const TrainCoupling clutch = ThreeStages(20.0, 2.0 * kDeg, 500.0, 6.0 * kDeg, 3000.0);
  const TrainSpec spec = StagedDriveline(clutch, 30.0, 0.1);
  const GearTrain train = BuildGearTrain(spec);
  const TrainTables t = BuildTrainTablesAtTier(spec, train, Tier::kTier3);
  REQUIRE(t.meshes.size() == 3);
  const Eigen::VectorXd twist = (t.body_angles.row(0) - t.body_angles.row(1)).transpose();
  for (size_t i = 1; i < 3; ++i) {
    CHECK((t.meshes[i].v - twist).norm() <= 1e-12 * twist.norm());
  }
  const auto [z0, states] = TrainStaticState(t);
  CHECK(twist.dot(z0.head(t.n)) == Approx(train.couplings[0].MeanTwist()).epsilon(1e-8));
  CHECK(states[1] == ContactState::kDrive);
  CHECK(states[2] == ContactState::kFree);
}

// E = 1/2 x'^T M x' + 1/2 x^T K_0 x - f^T x + sum over contacts of 1/2 k g^2 on the flank in
// contact (a gear mesh's teeth, a stage's dead-band spring): conserved by the undamped system.
double Energy(const TrainTables& t, const Eigen::VectorXd& z) {
  const int n = t.n;
  const Eigen::VectorXd x = z.head(n), v = z.segment(n, n);
  double e = 0.5 * v.dot(t.inertia.cwiseProduct(v)) - t.force.dot(x);
  if (t.structural_stiffness.size() > 0) e += 0.5 * x.dot(t.structural_stiffness * x);
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    const int mesh = static_cast<int>(i);
    const double drive = t.GapValue(mesh, 0, true, z), back = t.GapValue(mesh, 0, false, z);
    if (drive > 0.0) e += 0.5 * t.meshes[i].k_drive[0] * drive * drive;
    if (back < 0.0) e += 0.5 * t.meshes[i].k_back[0] * back * back;
  }
  return e;
}

// The undamped staged driveline (constant mesh stiffness, no excitation) from its static state with
// the flywheel kicked by `kick` (rad/s) against the input, stepped for 0.5 s: the largest |E - E_0|
// over 200 samples, and the recorded statistics.
std::pair<double, TrainStatistics> EnergyDrift(const TrainCoupling& clutch, double kick) {
  const Model s(StagedDriveline(clutch, 30.0, 0.0));
  const TrainTables& t = s.tables;
  for (const TrainMeshTable& mt : t.meshes) {  // one stiffness and one wall per contact
    for (int j = 0; j < mt.segments(); ++j) {
      REQUIRE(mt.k_drive[static_cast<size_t>(j)] == mt.k_drive[0]);
      REQUIRE(mt.error[static_cast<size_t>(j)] == mt.error[0]);
    }
  }
  auto [z0, s0] = TrainStaticState(t);
  z0[t.n + 0] += kick;
  const double e0 = Energy(t, z0);
  TrainStepper stepper(t, {}, z0, s0);
  TrainRecorder recorder(t, 4, 0.0);
  double worst = 0.0;
  for (int k = 1; k <= 200; ++k) {
    REQUIRE(stepper.Run(0.0025 * k, &recorder));
    worst = std::max(worst, std::abs(Energy(t, stepper.state()) - e0));
  }
  return {worst, recorder.Result()};
}

TEST_CASE("coupling stages: an undamped oscillation conserves energy across stage changes",
          "[solver][train]") {
  // The exact solution conserves E through every stage change: each is located where the
  // dead-band spring starts, so no energy jumps there. Rounding: 1e-10 of the kick's energy
  // (1/2 J_fw kick^2) over 0.5 s of stepping (measured 1e-12 with hundreds of events).
  const double j_flywheel = 0.12;
  SECTION("in and out of stage 3, the gear mesh in permanent contact") {
    const double kick = 1.0;
    const auto [drift, stats] =
        EnergyDrift(ThreeStages(20.0, 3.5 * kDeg, 500.0, 4.5 * kDeg, 3000.0), kick);
    REQUIRE(stats.coupling_stages.size() == 2);
    INFO("drift " << drift << " J, stage 3 entries " << stats.coupling_stages[1].entries);
    CHECK(stats.coupling_stages[1].entries >= 4);
    CHECK(stats.meshes.at(0).separations == 0);
    CHECK(drift <= 1e-10 * 0.5 * j_flywheel * kick * kick);
  }
  SECTION("through both stage walls, the gear mesh rattling as well") {
    const double kick = 3.0;
    const auto [drift, stats] =
        EnergyDrift(ThreeStages(20.0, 2.0 * kDeg, 500.0, 5.0 * kDeg, 3000.0), kick);
    REQUIRE(stats.coupling_stages.size() == 2);
    INFO("drift " << drift << " J, stage 2 entries " << stats.coupling_stages[0].entries
                  << ", stage 3 entries " << stats.coupling_stages[1].entries);
    CHECK(stats.coupling_stages[0].entries >= 2);  // left stage 2 downwards and came back
    CHECK(stats.coupling_stages[1].entries >= 2);
    CHECK(stats.meshes.at(0).separations > 0);
    CHECK(drift <= 1e-10 * 0.5 * j_flywheel * kick * kick);
  }
}

TEST_CASE("coupling stages: a staged clutch damper under an engine order follows CVODE",
          "[solver][train]") {
  // Damped, engine order 2 on the flywheel: the twist crosses stage walls every firing cycle.
  // Every stage change (and any mesh event) paired with CVODE's (rtol 1e-13) and the TE within
  // 1e-8 of the TE's largest value over 12 mesh cycles.
  TrainSpec spec =
      StagedDriveline(ThreeStages(20.0, 2.0 * kDeg, 500.0, 5.0 * kDeg, 3000.0), 30.0, 0.2);
  spec.operating.excitation = {{2.0, 600.0, 0.0}};
  const Model s(spec);
  const double end = 12.0 * s.tables.meshes[0].period;
  const testing::ReferenceAgreement a = testing::AgreeWithReference(s.tables, end);
  testing::CheckRattleFollowsReference(a);
  // The events compared include stage changes.
  const auto [z0, s0] = TrainStaticState(s.tables);
  TrainStepper stepper(s.tables, {}, z0, s0);
  TrainRecorder recorder(s.tables, 4, 0.0);
  REQUIRE(stepper.Run(end, &recorder));
  const TrainStatistics stats = recorder.Result();
  INFO("stage 2 entries " << stats.coupling_stages.at(0).entries << ", stage 3 entries "
                          << stats.coupling_stages.at(1).entries);
  CHECK(stats.coupling_stages[0].entries + stats.coupling_stages[1].entries >= 2);
}

TEST_CASE("coupling stages: certified jumps hold a free stage between its walls",
          "[solver][train]") {
  // In stage 2 under a small engine order, the mesh in permanent contact: stage 3 stays free and
  // is certified between its walls (+-6 deg); jumped and stepped runs record the same orbit (TE
  // RMS to 1e-10 of the TE p-p, CheckJumpsMatchStepping).
  TrainSpec spec =
      StagedDriveline(ThreeStages(20.0, 2.0 * kDeg, 500.0, 6.0 * kDeg, 3000.0), 30.0, 0.2);
  spec.operating.excitation = {{2.0, 50.0, 0.0}};
  const Model s(spec);
  REQUIRE(LoadedContactStates(s.tables)[2] == ContactState::kFree);
  testing::CheckJumpsMatchStepping(s.tables);
}

TEST_CASE("coupling stages: the coupling's torque statistics add its stages exactly",
          "[solver][train]") {
  // Undamped couplings at rest plus a kick: the torque's maximum is the curve at the largest
  // twist (both certified extrema of the same exact trajectory), to 1e-9 of it.
  const TrainCoupling clutch = ThreeStages(20.0, 2.0 * kDeg, 500.0, 5.0 * kDeg, 3000.0);
  const Model s(StagedDriveline(clutch, 30.0, 0.0));
  const TrainTables& t = s.tables;
  auto [z0, s0] = TrainStaticState(t);
  z0[t.n + 0] += 3.0;
  TrainStepper stepper(t, {}, z0, s0);
  TrainRecorder recorder(t, 4, 0.0);
  Eigen::MatrixXd rows = Eigen::MatrixXd::Zero(2, t.m);
  rows(0, 0) = 1.0;
  rows(0, 1) = -1.0;
  rows.row(1) = clutch.stiffness * rows.row(0);
  recorder.TrackOutputs(rows, {{1, 1, 1.0}, {1, 2, 1.0}});
  REQUIRE(stepper.Run(0.3, &recorder));
  const TrainStatistics stats = recorder.Result();
  REQUIRE(stats.outputs.size() == 2);
  const CouplingSprings springs = clutch.springs();
  INFO("twist " << stats.outputs[0].min / kDeg << " to " << stats.outputs[0].max / kDeg << " deg");
  CHECK(stats.outputs[0].max > 5.0 * kDeg);  // reached stage 3
  CHECK(stats.outputs[1].max == Approx(springs.Torque(stats.outputs[0].max)).epsilon(1e-9));
  CHECK(stats.outputs[1].min == Approx(springs.Torque(stats.outputs[0].min)).epsilon(1e-9));
}

}  // namespace
}  // namespace gearnvh
