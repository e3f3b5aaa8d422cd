// Torsional couplings between shafts (issue 39 item 2, TrainSpec::couplings): the speeds and
// torques they carry, the rules on them, and the motion they give, against closed forms and CVODE.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "gearnvh/reduction/train_reduction.h"
#include "gearnvh/solver/train_rate_bound.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

using Model = testing::TrainModel;

TrainCoupling CouplingOf(const std::string& name, const std::string& a, const std::string& b,
                         double stiffness, double damping) {
  TrainCoupling c;
  c.name = name;
  c.shaft_a = a;
  c.shaft_b = b;
  c.stiffness = stiffness;
  c.damping = damping;
  return c;
}

// A driveline in gear: flywheel -(clutch damper)- input (g1, 20) -> output (g2, 30) -(halfshaft)-
// wheels, the speed given on the flywheel and the vehicle's road load on the wheels.
constexpr int kFlywheelBody = 0, kInputBody = 1, kOutputBody = 2, kWheelsBody = 3;
TrainSpec Driveline(double clutch_stiffness, double load) {
  TrainSpec t;
  t.name = "driveline";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {testing::RigidShaft("flywheel", 0.12), testing::RigidShaft("input", 2e-3),
              testing::RigidShaft("output", 3e-3), testing::RigidShaft("wheels", 8.0)};
  t.gears = {testing::TrainGearOf("g1", "input", 20), testing::TrainGearOf("g2", "output", 30)};
  t.meshes = {testing::TrainMeshOf("g1", "g2")};
  t.couplings = {CouplingOf("clutch_damper", "flywheel", "input", clutch_stiffness, 0.05),
                 CouplingOf("halfshaft", "output", "wheels", 12000.0, 5.0)};
  t.operating.input_shaft = "flywheel";
  t.operating.speed = 800.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"wheels", load}};
  t.analysis.segments_per_cycle = 16;
  return t;
}

TEST_CASE("coupling: speeds pass through it 1:1 and it carries the torque flow",
          "[solver][train]") {
  const TrainSpec spec = Driveline(500.0, 30.0);
  REQUIRE_NOTHROW(ValidateTrainSpec(spec));
  const GearTrain train = BuildGearTrain(spec);
  const std::vector<TrainBody>& bodies = train.topology.bodies;
  const double w = spec.operating.speed;
  CHECK(bodies[kInputBody].speed == w);
  CHECK(bodies[kOutputBody].speed == Approx(-w * 20.0 / 30.0).epsilon(1e-15));
  CHECK(bodies[kWheelsBody].speed == bodies[kOutputBody].speed);
  CHECK(train.topology.parent_coupling[kInputBody] == 0);
  CHECK(train.topology.parent_coupling[kWheelsBody] == 1);
  CHECK(train.topology.ParentBody(spec, kWheelsBody) == kOutputBody);
  // Power balance without friction: the flywheel supplies 30 N m at the wheels' speed; the
  // halfshaft carries 30 N m from the output to the wheels, the clutch damper the input torque
  // from the flywheel to the input, the mesh 30 N m on g2. Closed forms to rounding (1e-14).
  CHECK(train.input_torque == Approx(30.0 * 20.0 / 30.0).epsilon(1e-14));
  REQUIRE(train.couplings.size() == 2);
  CHECK(train.couplings[0].mean_torque == Approx(train.input_torque).epsilon(1e-14));
  CHECK(train.couplings[1].mean_torque == Approx(30.0).epsilon(1e-14));
  CHECK(train.couplings[1].MeanTwist() == Approx(30.0 / 12000.0).epsilon(1e-14));
  CHECK(train.meshes[0].transmitted_torque == Approx(30.0).epsilon(1e-14));
  CHECK_FALSE(train.meshes[0].back_flank_loaded);
  // Written the other way round, [input, flywheel], the input drives "backwards": -T.
  TrainSpec reversed = spec;
  std::swap(reversed.couplings[0].shaft_a, reversed.couplings[0].shaft_b);
  CHECK(BuildGearTrain(reversed).couplings[0].mean_torque ==
        Approx(-train.input_torque).epsilon(1e-14));
  // The static state of the tables twists each coupling by its mean torque over k: the clutch
  // damper by 20 N m / 500 N m/rad = 0.04 rad (rounding of a static solve: 1e-10 relative).
  const TrainTables t = BuildTrainTables(spec, train);
  const Eigen::VectorXd x = TrainStaticState(t).first.head(t.n);
  CHECK(x[kFlywheelBody] - x[kInputBody] == Approx(train.couplings[0].MeanTwist()).epsilon(1e-10));
  // The output and wheels turn -z: in their own sense the twist is x_out - x_wheels.
  CHECK(x[kOutputBody] - x[kWheelsBody] == Approx(train.couplings[1].MeanTwist()).epsilon(1e-10));
  // Tier 3 (the structure, the coupling on the body nodes' th_z): the wheels' and the flywheel's
  // statics hold only the coupling against the load or the input torque, so the twists are the
  // same T / k whatever the lateral DOF do (a static solve of a reduced model: 1e-8).
  const TrainTables three = BuildTrainTablesAtTier(spec, train, Tier::kTier3, {});
  const Eigen::VectorXd angles = three.body_angles * TrainStaticState(three).first.head(three.n);
  CHECK(angles[kFlywheelBody] - angles[kInputBody] ==
        Approx(train.couplings[0].MeanTwist()).epsilon(1e-8));
  CHECK(angles[kOutputBody] - angles[kWheelsBody] ==
        Approx(train.couplings[1].MeanTwist()).epsilon(1e-8));
}

TEST_CASE("coupling: the rules name the coupling, its value and why", "[solver][train]") {
  const auto error_of = testing::ValidationError;
  TrainSpec spec = Driveline(500.0, 30.0);
  spec.couplings[0].shaft_b = "g1";  // a gear, not a shaft
  CHECK(error_of(spec).first == "couplings.clutch_damper.between");
  CHECK_THAT(error_of(spec).second, Catch::Contains("'g1' is a gear (on shaft 'input')"));
  spec = Driveline(500.0, 30.0);
  spec.couplings[0].shaft_b = "flywheel";
  CHECK_THAT(error_of(spec).second, Catch::Contains("two different shafts"));
  spec = Driveline(500.0, 30.0);
  spec.couplings[0].stiffness = 0.0;
  CHECK(error_of(spec).first == "couplings.clutch_damper.stiffness");
  spec.couplings[0].stiffness = 2e8;
  CHECK(error_of(spec).first == "couplings.clutch_damper.stiffness");
  spec = Driveline(500.0, 30.0);
  spec.couplings[1].damping = -1.0;
  CHECK(error_of(spec).first == "couplings.halfshaft.damping");
  // Shafts at different speeds: a coupling from the input to the output closes a loop whose
  // ratios disagree (1 against -2/3).
  spec = Driveline(500.0, 30.0);
  spec.couplings.push_back(CouplingOf("bad", "input", "output", 100.0, 0.0));
  CHECK(error_of(spec).first == "couplings.bad.between");
  CHECK_THAT(error_of(spec).second, Catch::Contains("ratios disagree"));
  // Two couplings in parallel between one pair of shafts.
  spec = Driveline(500.0, 30.0);
  spec.couplings.push_back(CouplingOf("second", "input", "flywheel", 100.0, 0.0));
  CHECK(error_of(spec).first == "couplings.second.between");
  // A fixed shaft does not turn.
  spec = Driveline(500.0, 30.0);
  spec.shafts[kWheelsBody].fixed = true;
  spec.operating.loads = {{"output", 30.0}};
  CHECK(error_of(spec).first == "couplings.halfshaft.between");
  CHECK_THAT(error_of(spec).second, Catch::Contains("fixed"));
  // A coupled shaft with nothing on it is its own body: it needs an inertia.
  spec = Driveline(500.0, 30.0);
  spec.shafts[kFlywheelBody].inertia = 0.0;
  CHECK(error_of(spec).first == "shafts.flywheel.inertia");
  // Without the clutch damper the shaft "input" (the speed is given on the flywheel) has no way
  // to turn.
  spec = Driveline(500.0, 30.0);
  spec.couplings.erase(spec.couplings.begin());
  CHECK(error_of(spec).first == "shafts.input");
}

TEST_CASE("coupling: one in parallel with a gear path is refused, and so is an elastic shaft",
          "[solver][train]") {
  // input -(g1 20 : g2 30)- mid -(g3 30 : g4 20)- output, and a coupling input - output in
  // parallel (one speed: 20/30 x 30/20). Its preload at assembly is not in the file: refused, at
  // the coupling whatever order the search meets the paths in (the gears are searched first).
  TrainSpec spec;
  spec.name = "parallel";
  spec.materials["steel"] = Material{206e9, 0.3, 7850.0};
  spec.shafts = {testing::RigidShaft("input", 2e-3), testing::RigidShaft("mid", 1e-3),
                 testing::RigidShaft("output", 2e-3)};
  spec.gears = {testing::TrainGearOf("g1", "input", 20), testing::TrainGearOf("g2", "mid", 30),
                testing::TrainGearOf("g3", "mid", 30), testing::TrainGearOf("g4", "output", 20)};
  spec.meshes = {testing::TrainMeshOf("g1", "g2"), testing::TrainMeshOf("g3", "g4")};
  spec.couplings = {CouplingOf("parallel", "input", "output", 1000.0, 0.0)};
  spec.operating.input_shaft = "input";
  spec.operating.speed = 100.0;
  spec.operating.loads = {{"output", 10.0}};
  try {
    ValidateTrainSpec(spec);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "couplings.parallel.between");
    CHECK_THAT(e.rule(), Catch::Contains("closes a loop"));
  }
  // Between shafts at different speeds it is told so, at the coupling.
  spec.gears[2].gear.teeth = 25;
  spec.gears[3].gear.teeth = 25;
  try {
    ValidateTrainSpec(spec);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "couplings.parallel.between");
    CHECK_THAT(e.rule(), Catch::Contains("ratios disagree"));
  }
  // An elastic shaft has no attachment point for a coupling yet: refused, naming it.
  TrainSpec elastic = Driveline(500.0, 30.0);
  elastic.shafts[kFlywheelBody].inertia.reset();
  elastic.shafts[kFlywheelBody].elastic = testing::ElasticShaftSpec();
  try {
    ValidateTrainSpec(elastic);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "couplings.clutch_damper.between");
    CHECK_THAT(e.rule(), Catch::Contains("elastic shaft 'flywheel'"));
  }
}

TEST_CASE("coupling: tier-1 frequencies of a three-inertia chain are the closed form",
          "[solver][train]") {
  // flywheel J1 -k1- input J2 -mesh- output J3 (no halfshaft: the load on the output). Referred to
  // the input, the mesh is a torsional spring k2 = k_m r_a^2 to J3' = J3 (r_a / r_b)^2, and the
  // free-free chain's two frequencies solve
  //   w^4 - w^2 [k1 (1/J1 + 1/J2) + k2 (1/J2 + 1/J3')] + k1 k2 (J1 + J2 + J3') / (J1 J2 J3') = 0.
  TrainSpec spec = Driveline(500.0, 30.0);
  spec.shafts.pop_back();
  spec.couplings.pop_back();
  spec.operating.loads = {{"output", 20.0}};
  const GearTrain train = BuildGearTrain(spec);
  const TrainTorsionalModes modes = TorsionalModes(train);
  REQUIRE(modes.free_rotations == 1);
  REQUIRE(modes.frequencies_hz.size() == 2);
  const TrainMeshModel& mesh = train.meshes[0];
  const double ra = mesh.geometry.pinion.base, rb = mesh.geometry.wheel.base;
  const double j1 = train.body_inertia[kFlywheelBody], j2 = train.body_inertia[kInputBody];
  const double j3 = train.body_inertia[kOutputBody] * (ra / rb) * (ra / rb);
  const double k1 = 500.0, k2 = mesh.stiffness.mean * ra * ra;
  const double b = k1 * (1.0 / j1 + 1.0 / j2) + k2 * (1.0 / j2 + 1.0 / j3);
  const double c = k1 * k2 * (j1 + j2 + j3) / (j1 * j2 * j3);
  const double root = std::sqrt(b * b - 4.0 * c);
  const double low = std::sqrt((b - root) / 2.0) / (2.0 * std::numbers::pi);
  const double high = std::sqrt((b + root) / 2.0) / (2.0 * std::numbers::pi);
  INFO("closed form " << low << ", " << high << " Hz");
  // A symmetric eigensolve of a 3 x 3 pencil whose stiffnesses (k2 / k1) differ by about 120:
  // 1e-9 relative (the low root of the quadratic loses ~k2/k1 eps to cancellation).
  CHECK(modes.frequencies_hz[0] == Approx(low).epsilon(1e-9));
  CHECK(modes.frequencies_hz[1] == Approx(high).epsilon(1e-9));
  // The structure (rigid shafts on their supports, the mesh's lateral terms) keeps one free
  // rotation, and its lowest mode is the clutch damper's: within 2e-3 of tier 1's (the supports'
  // lateral compliance softens the mesh, which that mode hardly moves: measured 4.7e-4; a
  // coupling left out of the structure moves it to 0 Hz, one at half its stiffness by 29 %).
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  CHECK(structure.free_rotations.cols() == 1);
  const TrainReducedModel full = ReduceTrain(structure, Tier::kTier3);
  REQUIRE(!full.natural_frequencies_hz.empty());
  CHECK(full.natural_frequencies_hz[0] == Approx(low).epsilon(2e-3));
}

// The rattler (input g1 20 -> layshaft g2 30, g3 25 -> loose g4 on the input) behind a flywheel
// and a clutch damper; the engine's order 2 on the flywheel.
TrainSpec RattlerBehindDamper(double stiffness, double damping, double acceleration) {
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.shafts.insert(spec.shafts.begin(), testing::RigidShaft("flywheel", 0.01));
  spec.couplings = {CouplingOf("clutch_damper", "flywheel", "input", stiffness, damping)};
  spec.operating.input_shaft = "flywheel";
  spec.operating.excitation = {{2.0, acceleration, 0.0}};
  return spec;
}

TEST_CASE("coupling: a rattling train behind a clutch damper follows CVODE event by event",
          "[solver][train]") {
  // The clutch damper's spring and damper join the flywheel and the input in every generator.
  // Tolerance as the rattle test of train_excitation_test.cc: 1e-8 of the TE over two mesh cycles
  // (CVODE at rtol 1e-13 through a few impacts).
  const Model s(RattlerBehindDamper(2000.0, 0.05, 1500.0));
  testing::CheckRattleFollowsReference(
      testing::AgreeWithReference(s.tables, 2.0 * s.tables.meshes[0].period));
}

TEST_CASE("coupling: certified jumps over a driveline with a clutch damper and a halfshaft",
          "[solver][train]") {
  // In permanent contact under engine order 2 on the flywheel: jumped and stepped runs record the
  // same orbit (TE RMS to 1e-10 of the TE p-p, as the reducer's own jump test).
  TrainSpec spec = Driveline(500.0, 30.0);
  spec.operating.excitation = {{2.0, 50.0, 0.0}};
  const Model s(spec);
  testing::CheckJumpsMatchStepping(s.tables);
}

TEST_CASE("coupling: an undamped coupling's energy is conserved in permanent contact",
          "[solver][train]") {
  // Undamped everywhere (mesh damping ratio 0, c = 0), the driveline's meshes held in drive
  // contact and no excitation: the flywheel kicked by 1 rad/s against the input. Over one mesh
  // segment the tuple is one LTI system, so E = 1/2 x'^T M x' + 1/2 x^T K x - f^T x is constant
  // (time-varying mesh stiffness changes it at segment boundaries only: checked within the first
  // segment). Rounding: 1e-12 of E.
  TrainSpec spec = Driveline(500.0, 30.0);
  spec.couplings[0].damping = 0.0;
  spec.couplings[1].damping = 0.0;
  spec.meshes[0].mesh.damping_ratio = 0.0;
  const Model s(spec);
  const TrainTables& t = s.tables;
  auto [z0, s0] = TrainStaticState(t);
  z0[t.n + kFlywheelBody] += 1.0;
  const TuplePencil p = AssembleTuplePencil(t, {0}, s0);
  const auto energy = [&](const Eigen::VectorXd& z) {
    const Eigen::VectorXd x = z.head(t.n), v = z.segment(t.n, t.n);
    return 0.5 * v.dot(t.inertia.cwiseProduct(v)) + 0.5 * x.dot(p.K * x) - p.force.dot(x);
  };
  const double e0 = energy(z0);
  const double segment = t.meshes[0].boundary[1] - t.meshes[0].boundary[0];
  TrainStepper stepper(t, {}, z0, s0);
  double worst = 0.0;
  for (int k = 1; k <= 20; ++k) {
    REQUIRE(stepper.Run(0.05 * k * segment * 0.99));
    worst = std::max(worst, std::abs(energy(stepper.state()) - e0));
  }
  REQUIRE(stepper.summary().events == 0);
  INFO("energy " << e0 << " J, drift " << worst);
  CHECK(worst <= 1e-12 * std::abs(e0));
}

}  // namespace
}  // namespace gearnvh
