// Gear trains (docs/gear-trains.md): topology, nominal speeds, torque flow, tier-1 torsional modes.
#include "gearnvh/model/gear_train.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "model/test_specs.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

// The hand-built pieces of tests/model/test_trains.h under short names.
TrainGear Gear(const std::string& name, const std::string& shaft, int teeth,
               Mounting mounting = Mounting::kFixed) {
  return testing::TrainGearOf(name, shaft, teeth, mounting);
}
constexpr auto Rigid = testing::RigidShaft;
constexpr auto Mesh = [](const std::string& a, const std::string& b, double backlash = 100e-6) {
  return testing::TrainMeshOf(a, b, backlash);
};

// Input (g1, 20) -> layshaft (g2, 40; g3, 18) -> output (g4, 54), and a loose gear g5 (30) on the
// output shaft driven by g6 (25) on the layshaft.
TrainSpec TwoStage() {
  TrainSpec t;
  t.name = "two-stage";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {Rigid("input", 5e-3), Rigid("layshaft", 1e-3), Rigid("output", 0.2)};
  t.gears = {Gear("g1", "input", 20),
             Gear("g2", "layshaft", 40),
             Gear("g3", "layshaft", 18),
             Gear("g4", "output", 54),
             Gear("g5", "output", 30, Mounting::kLoose),
             Gear("g6", "layshaft", 25)};
  // g6-g5 at the layshaft-output centre distance of g3-g4 (72 teeth at 2 mm).
  t.gears[4].gear.module = t.gears[5].gear.module = 2e-3 * 72.0 / 55.0;
  t.meshes = {Mesh("g1", "g2"), Mesh("g3", "g4"), Mesh("g6", "g5")};
  t.operating.input_shaft = "input";
  t.operating.speed = 1000.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"output", 30.0}, {"g5", 0.2}};
  return t;
}

TEST_CASE("train topology: bodies and nominal speeds through the meshes", "[train]") {
  const TrainSpec spec = TwoStage();
  REQUIRE_NOTHROW(ValidateTrainSpec(spec));
  const TrainTopology t = AnalyseTrainTopology(spec);
  REQUIRE(t.bodies.size() == 4);  // three shafts and the loose gear
  const double w = spec.operating.speed;
  // omega_b = -omega_a z_a / z_b, exact in a few roundings.
  CHECK(t.bodies[0].speed == Approx(w).epsilon(1e-15));
  CHECK(t.bodies[1].speed == Approx(-w * 20.0 / 40.0).epsilon(1e-14));
  CHECK(t.bodies[2].speed == Approx(w * 20.0 / 40.0 * 18.0 / 54.0).epsilon(1e-14));
  CHECK(t.bodies[3].kind == BodyKind::kLooseGear);
  CHECK(t.bodies[3].speed == Approx(w * 20.0 / 40.0 * 25.0 / 30.0).epsilon(1e-14));
  CHECK(t.gear_body[4] == 3);
  CHECK(t.gear_body[5] == 1);
}

TEST_CASE("train torque flow balances the loads by power", "[train]") {
  const TrainSpec spec = TwoStage();
  const GearTrain train = BuildGearTrain(spec);
  const double w_in = spec.operating.speed, w_lay = w_in * 0.5, w_out = w_lay / 3.0,
               w_loose = w_lay * 25.0 / 30.0;
  // Power balance: T_in w_in = 30 w_out + 0.2 w_loose; mesh g3-g4 carries the output torque on
  // g4, mesh g6-g5 the drag on g5, mesh g1-g2 both, as a torque on g2 (the layshaft).
  CHECK(train.input_torque == Approx((30.0 * w_out + 0.2 * w_loose) / w_in).epsilon(1e-14));
  CHECK(train.meshes[1].transmitted_torque == Approx(30.0).epsilon(1e-14));
  CHECK(train.meshes[2].transmitted_torque == Approx(0.2).epsilon(1e-14));
  CHECK(train.meshes[0].transmitted_torque ==
        Approx((30.0 * w_out + 0.2 * w_loose) / w_lay).epsilon(1e-14));
  for (const TrainMeshModel& m : train.meshes) CHECK_FALSE(m.back_flank_loaded);
  // The mesh's load along the line of action: T / r_b of the driven gear.
  CHECK(train.meshes[1].cycle.load ==
        Approx(30.0 / train.meshes[1].geometry.wheel.base).epsilon(1e-14));
}

TEST_CASE("a two-mesh torsional train's frequencies equal the closed-form eigenproblem",
          "[train]") {
  TrainSpec spec = TwoStage();
  spec.gears.pop_back();  // no loose gear: input, layshaft, output
  spec.gears.pop_back();
  spec.meshes.pop_back();
  spec.operating.loads = {{"output", 30.0}};
  const GearTrain train = BuildGearTrain(spec);
  const TrainTorsionalModes modes = TorsionalModes(train);
  REQUIRE(modes.frequencies_hz.size() == 2);
  // The free rotation th_j ~ |w_j| strains no mesh: r_b,a |w_a| = r_b,b |w_b| (equal base-circle
  // speeds) to rounding, so K annihilates it.
  Eigen::Vector3d rigid;
  for (int b = 0; b < 3; ++b)
    rigid(b) = std::abs(train.topology.bodies[static_cast<size_t>(b)].speed);
  CHECK((modes.K * rigid).norm() <= 1e-13 * modes.K.norm() * rigid.norm());
  // Shapes M-orthonormal.
  const Eigen::MatrixXd gram = modes.shapes.transpose() * modes.M * modes.shapes;
  CHECK((gram - Eigen::MatrixXd::Identity(2, 2)).norm() < 1e-12);
  // K = k1 u u^T + k2 w w^T, u = (r1, -r2, 0), w = (0, r3, -r4); the nonzero eigenvalues of
  // A = M^-1 K solve l^2 - tr(A) l + S = 0, S the sum of A's principal 2x2 minors.
  const double k1 = train.meshes[0].stiffness.mean, k2 = train.meshes[1].stiffness.mean;
  const double r1 = train.meshes[0].geometry.pinion.base, r2 = train.meshes[0].geometry.wheel.base;
  const double r3 = train.meshes[1].geometry.pinion.base, r4 = train.meshes[1].geometry.wheel.base;
  const double J1 = train.body_inertia[0], J2 = train.body_inertia[1], J3 = train.body_inertia[2];
  const double a11 = k1 * r1 * r1 / J1, a12 = -k1 * r1 * r2 / J1, a21 = -k1 * r1 * r2 / J2,
               a22 = (k1 * r2 * r2 + k2 * r3 * r3) / J2, a23 = -k2 * r3 * r4 / J2,
               a32 = -k2 * r3 * r4 / J3, a33 = k2 * r4 * r4 / J3;
  const double tr = a11 + a22 + a33;
  const double s = (a11 * a22 - a12 * a21) + a11 * a33 + (a22 * a33 - a23 * a32);
  const double disc = std::sqrt(tr * tr - 4.0 * s);
  const double f_low = std::sqrt(0.5 * (tr - disc)) / (2 * std::numbers::pi);
  const double f_high = std::sqrt(0.5 * (tr + disc)) / (2 * std::numbers::pi);
  // The shift-invert eigensolver is accurate to ~1e-12 relative on a 3x3 pencil; the quadratic's
  // cancellation in tr - disc costs at most tr / (tr - disc) ~ 1e2 more.
  CHECK(modes.frequencies_hz[0] == Approx(f_low).epsilon(1e-9));
  CHECK(modes.frequencies_hz[1] == Approx(f_high).epsilon(1e-9));
  // Body inertias: the rigid shaft's own plus its gears' solid disks.
  const GearSpec& g2 = spec.gears[1].gear;
  const double rp = 0.5 * g2.module * g2.teeth, rb = 0.5 * g2.bore_diameter;
  const double m2 = 7850.0 * std::numbers::pi * (rp * rp - rb * rb) * g2.face_width;
  const GearSpec& g3 = spec.gears[2].gear;
  const double rp3 = 0.5 * g3.module * g3.teeth, rb3 = 0.5 * g3.bore_diameter;
  const double m3 = 7850.0 * std::numbers::pi * (rp3 * rp3 - rb3 * rb3) * g3.face_width;
  CHECK(J2 == Approx(1e-3 + 0.5 * m2 * (rp * rp + rb * rb) + 0.5 * m3 * (rp3 * rp3 + rb3 * rb3))
                  .epsilon(1e-13));
}

TEST_CASE("a schema-1 gearbox is the two-shaft train with the same mesh model", "[train]") {
  GearboxSpec spec = testing::StandardPair(27, 43);
  spec.operating.torque = 40.0;
  const TrainSpec train_spec = TrainOf(spec);
  REQUIRE_NOTHROW(ValidateTrainSpec(train_spec));
  const GearTrain train = BuildGearTrain(train_spec);
  const ComponentModel model = BuildComponentModel(spec);
  REQUIRE(train.meshes.size() == 1);
  // The same function on the same inputs: bitwise equal.
  CHECK(train.meshes[0].stiffness.mean == model.mesh_summary.mean);
  CHECK(train.meshes[0].stiffness.lste_peak_to_peak == model.mesh_summary.lste_peak_to_peak);
  CHECK(train.meshes[0].cycle.load == model.cycle.load);
  CHECK(train.body_inertia[0] == model.pinion_body.polar);
  CHECK(train.body_inertia[1] == model.wheel_body.polar);
  // One mesh: f = sqrt(k (r1^2 / J1 + r2^2 / J2)) / 2 pi.
  const TrainTorsionalModes modes = TorsionalModes(train);
  const double r1 = model.geometry.pinion.base, r2 = model.geometry.wheel.base;
  const double f = std::sqrt(model.mesh_summary.mean * (r1 * r1 / model.pinion_body.polar +
                                                        r2 * r2 / model.wheel_body.polar)) /
                   (2 * std::numbers::pi);
  REQUIRE(modes.frequencies_hz.size() == 1);
  CHECK(modes.frequencies_hz[0] == Approx(f).epsilon(1e-10));
}

TEST_CASE("a schema-1 gearbox loaded on its pinion is the train loaded on its output by z2/z1",
          "[train]") {
  // torque_on: pinion: the wheel resists T1 z2 / z1, so the mesh carries the same force either way.
  GearboxSpec spec = testing::StandardPair(27, 43);
  spec.operating.torque = 25.0;
  spec.operating.torque_on = TorqueOn::kPinion;
  spec.operating.torque_unit = {"lbf*ft", 0.7375621492772654};
  const TrainSpec train_spec = TrainOf(spec);
  REQUIRE(train_spec.operating.loads.size() == 1);
  CHECK(train_spec.operating.loads[0].on == "output");
  CHECK(train_spec.operating.loads[0].torque == Approx(25.0 * 43.0 / 27.0).epsilon(1e-15));
  CHECK(train_spec.operating.loads[0].torque_unit.symbol == "lbf*ft");
  const GearTrain train = BuildGearTrain(train_spec);
  const ComponentModel model = BuildComponentModel(spec);
  // x z2 / z1 / ratio: a few roundings of 1e-16 between the two paths.
  CHECK(train.meshes[0].cycle.load == Approx(model.cycle.load).epsilon(1e-14));
  CHECK(train.input_torque == Approx(25.0).epsilon(1e-14));
}

TEST_CASE("GearboxOf takes back the train TrainOf makes of a schema-1 gearbox, bit for bit",
          "[train]") {
  // Every field a schema-1 file can set, on elastic and rigid shafts, loaded on either gear.
  GearboxSpec elastic = testing::FlexibleShaftsPair();
  elastic.name = "round trip";
  elastic.pinion.helix_angle = 15.0 * testing::kDeg;
  elastic.wheel.helix_angle = 15.0 * testing::kDeg;
  elastic.wheel.hand = Hand::kLeft;
  elastic.pinion.runout = Runout{5e-6, 0.3};
  elastic.wheel.pitch_errors = std::vector<double>(47, 1e-6);
  elastic.pinion.tip_relief = TipRelief{10e-6, 2e-3};
  elastic.mesh.friction_coefficient = 0.05;
  elastic.mesh.center_distance = 0.12;
  elastic.mesh.stiffness = FourierStiffness{3e8, {2e7}, {1e7}};
  elastic.mesh.static_transmission_error = {{1e-6}, {0.2}};
  elastic.operating.torque = 120.0;
  elastic.operating.torque_on = TorqueOn::kPinion;
  elastic.operating.torque_unit = {"lbf*ft", 0.7375621492772654};
  elastic.operating.speed_unit = {"rpm", 60.0 / (2.0 * std::numbers::pi)};
  elastic.operating.excitation = {{2.0, 300.0, 0.1}, {4.0, 50.0, -0.4}};
  elastic.analysis.tier = Tier::kTier3;
  elastic.analysis.cycles = 77;
  elastic.analysis.atlas_x = AtlasAxis{"mesh.backlash", {50e-6, 200e-6, 4, AxisScale::kLog}};
  const GearboxSpec rigid = testing::StandardPair(27, 43);
  for (const GearboxSpec& pair : {elastic, rigid}) {
    const TrainSpec train = TrainOf(pair);
    CHECK(IsSchemaOnePair(train));
    CHECK(GearboxOf(train) == pair);
  }
  // The load a pinion torque means is on the output; GearboxOf shows it on the pinion again.
  CHECK(TrainOf(elastic).operating.loads[0].pinion_torque == 120.0);
  CHECK(GearboxOf(TrainOf(elastic)).operating.torque_on == TorqueOn::kPinion);
  // A train of another form is not a schema-1 gearbox: GearboxOf refuses it.
  TrainSpec loose = TrainOf(rigid);
  loose.gears[1].mounting = Mounting::kLoose;
  CHECK_FALSE(IsSchemaOnePair(loose));
  CHECK_THROWS_AS(GearboxOf(loose), std::invalid_argument);
  TrainSpec heavy = TrainOf(rigid);
  heavy.shafts[0].inertia = 1e-3;  // a rigid shaft with inertia of its own: no schema-1 field
  CHECK_FALSE(IsSchemaOnePair(heavy));
  CHECK_FALSE(IsSchemaOnePair(TwoStage()));
}

TEST_CASE("one parameter registry: a pair's parameter is its train's", "[train][parameters]") {
  GearboxSpec pair = testing::StandardPair(27, 43);
  pair.operating.excitation = {{2.0, 300.0, 0.0}};
  // Each schema-1 name sets exactly its field (every other field compared with ==).
  for (const std::string& name : VariableParameters()) {
    INFO(name);
    GearboxSpec expected = pair;
    if (name == "operating.speed") expected.operating.speed = 0.125;
    if (name == "operating.torque") expected.operating.torque = 0.125;
    if (name == "mesh.backlash") expected.mesh.backlash = 0.125;
    if (name == "mesh.damping_ratio") expected.mesh.damping_ratio = 0.125;
    if (name == "mesh.friction_coefficient") expected.mesh.friction_coefficient = 0.125;
    if (name == "operating.excitation[0].amplitude") {
      expected.operating.excitation[0].amplitude = 0.125;
    }
    REQUIRE_FALSE(expected == pair);
    GearboxSpec set = pair;
    SetParameter(set, name, 0.125);
    CHECK(set == expected);
  }
  // A torque the file wrote on the pinion varies on the pinion; the train's output resists the
  // pair's WheelTorque(), the same expression, so the bits agree.
  pair.operating.torque_on = TorqueOn::kPinion;
  SetParameter(pair, "operating.torque", 30.0);
  CHECK(pair.operating.torque == 30.0);
  CHECK(pair.operating.torque_on == TorqueOn::kPinion);
  TrainSpec train = TrainOf(pair);
  SetTrainParameter(train, "operating.loads[0].torque", 12.0, "x");
  CHECK(train.operating.loads[0].pinion_torque == 12.0);
  CHECK(train.operating.loads[0].torque == GearboxOf(train).WheelTorque());  // same operations
  CHECK(train.operating.loads[0].torque == Approx(12.0 * 43.0 / 27.0).epsilon(1e-15));
  // A load that disagrees with its pinion torque is no schema-1 pair.
  train.operating.loads[0].torque *= 2.0;
  CHECK_FALSE(IsSchemaOnePair(train));
  // What the registry cannot set says why.
  GearboxSpec plain = testing::StandardPair(27, 43);
  CHECK_THROWS_WITH(SetParameter(plain, "operating.excitation[0].amplitude", 1.0),
                    Catch::Contains("no operating.excitation order to vary"));
  CHECK_THROWS_WITH(SetParameter(plain, "mesh.center_distance", 1.0),
                    Catch::Contains("must be one of operating.speed"));
  // A train's friction coefficient, per mesh.
  TrainSpec two_stage = TwoStage();
  CHECK(TrainParameterOf("meshes[1].friction_coefficient") == TrainParameter::kFrictionCoefficient);
  SetTrainParameter(two_stage, "meshes[1].friction_coefficient", 0.07, "x");
  CHECK(two_stage.meshes[1].mesh.friction_coefficient == 0.07);
  CHECK(two_stage.meshes[0].mesh.friction_coefficient == 0.0);
  // A load's viscous drag.
  CHECK(TrainParameterOf("operating.loads[1].viscous") == TrainParameter::kLoadViscous);
  SetTrainParameter(two_stage, "operating.loads[1].viscous", 2e-3, "x");
  CHECK(two_stage.operating.loads[1].viscous == 2e-3);
  CHECK_THROWS_WITH(SetTrainParameter(two_stage, "operating.loads[7].viscous", 1.0, "x"),
                    Catch::Contains("has 2 entries"));
}

std::string PathOfError(const TrainSpec& spec) {
  try {
    ValidateTrainSpec(spec);
  } catch (const InputError& e) {
    return e.path() + ": " + e.rule();
  }
  return "";
}

// Neutral at standstill: the output shaft stands (fixed), g4 and g5 idle on it, driven by the
// layshaft, each against its drag.
TrainSpec StandingOutput() {
  TrainSpec s = TwoStage();
  s.shafts[2].fixed = true;
  s.gears[3].mounting = Mounting::kLoose;
  s.operating.loads = {{"g4", 0.3}, {"g5", 0.2}};
  return s;
}

TEST_CASE("a drag relative to a fixed shaft is absolute, and counter-rotating shafts both resist",
          "[train]") {
  // g4 idles on the standing output: relative to it, its drag is on its own speed (the shaft is
  // the housing), one term, as if absolute.
  TrainSpec relative = StandingOutput();
  relative.operating.loads[0].viscous = 1e-3;
  TrainSpec absolute = relative;
  relative.operating.loads[0].relative_to = "output";
  const TrainTopology t = AnalyseTrainTopology(relative);
  const LoadAction a = ActionOfLoad(relative, t, 0), b = ActionOfLoad(absolute, t, 0);
  REQUIRE(a.terms.size() == 1);
  CHECK(a.terms[0].resisting == b.terms[0].resisting);
  CHECK(a.relative_speed == b.relative_speed);
  // T + c |W| with W = g4's speed.
  CHECK(a.terms[0].resisting == Approx(0.3 + 1e-3 * std::abs(t.bodies[3].speed)).epsilon(1e-15));
  // The layshaft relative to the input: dW = W_lay - W_in = -w/2 - w = -1.5 w. The drag resists
  // dW: +T about z on the layshaft, which turns about -z (so it resists its rotation), and the
  // reaction -T on the input, which turns about +z (it resists too): counter-rotating shafts both
  // lose, and the power T |dW| is the sum, T w/2 + T w.
  TrainSpec spec = TwoStage();
  spec.operating.loads.push_back({"layshaft", 0.5});
  spec.operating.loads.back().relative_to = "input";
  const TrainTopology u = AnalyseTrainTopology(spec);
  const LoadAction c = ActionOfLoad(spec, u, 2);
  REQUIRE(c.terms.size() == 2);
  CHECK(c.relative_speed == Approx(-1.5 * spec.operating.speed).epsilon(1e-15));
  CHECK(c.terms[0].resisting == 0.5);
  CHECK(c.terms[1].resisting == 0.5);
  REQUIRE_NOTHROW(ValidateTrainSpec(spec));
  // A GearTrain at another speed with a viscous drag is built again (its loads depend on speed).
  spec.operating.loads.back().viscous = 0.01;
  TrainSpec faster = spec;
  faster.operating.speed *= 1.5;
  const GearTrain moved = GearTrainAtSpeed(BuildGearTrain(spec), faster);
  const GearTrain built = BuildGearTrain(faster);
  CHECK(moved.input_torque == built.input_torque);
  CHECK(moved.meshes[0].transmitted_torque == built.meshes[0].transmitted_torque);
  CHECK(built.input_torque != BuildGearTrain(spec).input_torque);
}

TEST_CASE("a fixed shaft stands: loose gears on it turn, nothing may turn it", "[train]") {
  const TrainSpec spec = StandingOutput();
  REQUIRE_NOTHROW(ValidateTrainSpec(spec));
  const TrainTopology t = AnalyseTrainTopology(spec);
  REQUIRE(t.bodies.size() == 5);  // three shafts and the loose gears g4, g5
  const double w = spec.operating.speed;
  CHECK(t.bodies[2].speed == 0.0);
  CHECK(t.bodies[2].gears.empty());
  // The loose gears turn at the layshaft's speed times their meshes' ratios (exact in binary:
  // the same products as the topology's, so to rounding).
  const double layshaft = -w * 20.0 / 40.0;
  CHECK(t.bodies[3].speed == Approx(-layshaft * 18.0 / 54.0).epsilon(1e-15));
  CHECK(t.bodies[4].speed == Approx(-layshaft * 25.0 / 30.0).epsilon(1e-15));
  // Tier 1: the train's free rotation and the standing shaft's own (no mesh sees it).
  const GearTrain train = BuildGearTrain(spec);
  CHECK(TorsionalModes(train).free_rotations == 2);
  // The input carries the drags' power only.
  CHECK(train.input_torque ==
        Approx((0.3 * std::abs(t.bodies[3].speed) + 0.2 * std::abs(t.bodies[4].speed)) / w)
            .epsilon(1e-12));

  {
    TrainSpec s = spec;
    s.operating.loads.push_back({"output", 1.0});
    CHECK(PathOfError(s).rfind("operating.loads[2].on: is on the fixed shaft 'output'", 0) == 0);
  }
  {
    TrainSpec s = spec;
    s.gears[3].mounting = Mounting::kFixed;  // g4 fixed on the standing output meshes g3
    s.operating.loads = {{"g5", 0.2}};
    CHECK(PathOfError(s).rfind("meshes[1].gears: meshes gear 'g4', fixed on the fixed shaft "
                               "'output'",
                               0) == 0);
  }
  {
    TrainSpec s = spec;
    s.shafts[0].fixed = true;
    CHECK(PathOfError(s).rfind("operating.speed.shaft: names a fixed shaft", 0) == 0);
  }
  {
    TrainSpec s = spec;
    s.shafts[2].inertia = 0.0;  // the shaft alone is its body
    CHECK(
        PathOfError(s).rfind("shafts.output.inertia: must be > 0 on a fixed shaft that carries no "
                             "fixed gear",
                             0) == 0);
  }
}

TEST_CASE("train validation names the path and the rule", "[train][validation]") {
  {
    TrainSpec s = TwoStage();
    s.meshes[0].gear_b = "g6";  // g1 (input) with g6 (layshaft) is fine; g2 with g6 is not
    s.meshes[0].gear_a = "g2";
    CHECK(PathOfError(s).rfind("meshes[0].gears: the two gears sit on the same shaft", 0) == 0);
  }
  {
    TrainSpec s = TwoStage();
    s.meshes.pop_back();
    CHECK(PathOfError(s).rfind("gears.g5.mounting: a loose gear needs a mesh", 0) == 0);
  }
  {
    TrainSpec s = TwoStage();
    s.meshes[1].gear_b = "g9";
    CHECK(PathOfError(s).rfind("meshes[1].gears: must name a key of gears", 0) == 0);
  }
  {
    TrainSpec s = TwoStage();
    for (TrainGear& g : s.gears) {
      g.gear.helix_angle = 0.2;
      g.gear.hand = Hand::kRight;
    }
    CHECK(PathOfError(s).rfind("gears.g2.hand: must be the opposite", 0) == 0);
  }
  {
    TrainSpec s = TwoStage();
    s.gears[3].mounting = Mounting::kLoose;  // g4 loose: the output shaft has nothing to turn it
    CHECK(PathOfError(s).rfind("shafts.output: has no way to turn", 0) == 0);
  }
  {
    // A second path input -> layshaft whose ratio disagrees: g7 (20) on the input meshing g8 (50)
    // on the layshaft would turn it at -0.4 w_in, the first path at -0.5 w_in.
    TrainSpec s = TwoStage();
    s.gears.push_back(Gear("g7", "input", 20));
    s.gears.push_back(Gear("g8", "layshaft", 50));  // (another centre distance too: loop first)
    s.meshes.push_back(Mesh("g7", "g8"));
    CHECK(PathOfError(s).rfind("meshes[3].gears: closes a kinematic loop whose ratios disagree",
                               0) == 0);
  }
  {
    TrainSpec s = TwoStage();
    s.meshes[1].mesh.backlash = -1e-6;
    CHECK(PathOfError(s).rfind("meshes[1].backlash: must be > 0", 0) == 0);
  }
  {
    TrainSpec s = TwoStage();
    s.gears[3].gear.teeth = 3;
    CHECK(PathOfError(s).rfind("gears.g4.teeth: must be >= 6", 0) == 0);
  }
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("train rules: meshes between the same two shafts share one centre distance",
          "[train][validation]") {
  TrainSpec s = TwoStage();
  // g7 (20) on the layshaft with g8 (37) loose on the output: 57 mm, g3-g4 72 mm.
  s.gears.push_back(Gear("g7", "layshaft", 20));
  s.gears.push_back(Gear("g8", "output", 37, Mounting::kLoose));
  s.meshes.push_back(Mesh("g7", "g8"));
  const std::string error = PathOfError(s);
  INFO(error);
  CHECK(error.rfind("meshes[3].gears: joins shafts 'layshaft' and 'output' at a centre distance "
                    "of 57 mm, but meshes[1] (g3-g4) joins them at 72 mm",
                    0) == 0);
  s.gears.back().gear.teeth = 52;  // 72 mm: accepted
  CHECK(PathOfError(s).empty());
  // Within 1 % of the 2 mm module (20 um), as rounded drawing data gives it: accepted; beyond: not.
  s.meshes.back().mesh.center_distance = 72.015e-3;
  CHECK(PathOfError(s).empty());
  s.meshes.back().mesh.center_distance = 72.025e-3;
  CHECK(PathOfError(s).rfind("meshes[3].center_distance: joins shafts", 0) == 0);
}

TEST_CASE("train rules: an implausible module or helix angle is blamed on its own gear",
          "[train][validation]") {
  TrainSpec s = TwoStage();
  s.gears[0].gear.module = 2.0;  // "module: 2", read as 2 m, on the first gear of meshes[0]
  CHECK(PathOfError(s).rfind("gears.g1.module: must be in [", 0) == 0);
  s = TwoStage();
  s.gears[0].gear.helix_angle = 28.0;  // "helix_angle: 28", read as radians
  CHECK(PathOfError(s).rfind("gears.g1.helix_angle: must be in [", 0) == 0);
}

TEST_CASE("train rules: a gear may not have a shaft's name", "[train][validation]") {
  TrainSpec s = TwoStage();
  s.gears[4].name = "layshaft";  // the loose gear g5
  s.meshes[2].gear_b = "layshaft";
  s.operating.loads[1].on = "layshaft";
  CHECK(PathOfError(s).rfind("gears.layshaft: has the name of shafts.layshaft", 0) == 0);
}

TEST_CASE("train rules: a loop's error names the odd one of parallel meshes",
          "[train][validation]") {
  TrainSpec s;
  s.name = "parallel";
  s.materials["steel"] = Material{206e9, 0.3, 7850.0};
  s.shafts = {Rigid("input", 5e-3), Rigid("output", 0.2)};
  // Three meshes on the same two shafts at 56 mm; the first (25:31) disagrees with the two 19:37.
  s.gears = {Gear("e", "input", 25),  Gear("f", "output", 31), Gear("a", "input", 19),
             Gear("b", "output", 37), Gear("c", "input", 19),  Gear("d", "output", 37)};
  s.meshes = {Mesh("e", "f"), Mesh("a", "b"), Mesh("c", "d")};
  s.operating.input_shaft = "input";
  s.operating.speed = 100.0;
  s.operating.loads = {{"output", 10.0}};
  const std::string error = PathOfError(s);
  INFO(error);
  CHECK(error.rfind("meshes[0].gears: closes a kinematic loop whose ratios disagree", 0) == 0);
  CHECK(error.find("the other path (meshes[1], meshes[2])") != std::string::npos);
}

TEST_CASE("train rules: the size of a train is limited before any work", "[train][validation]") {
  using L = GearboxLimits;
  TrainSpec s = TwoStage();
  while (s.gears.size() <= L::kMaxTrainGears) s.gears.push_back(Gear("x", "layshaft", 40));
  CHECK(PathOfError(s).rfind("gears: must have at most 256 gears", 0) == 0);
  // g1 meshing 13 gears of 40 teeth on the layshaft besides g2 (consistent ratios and distances).
  s = TwoStage();
  for (size_t k = 0; k < L::kMaxMeshesPerGear; ++k) {
    s.gears.push_back(Gear("h" + std::to_string(k), "layshaft", 40));
    s.meshes.push_back(Mesh("g1", s.gears.back().name));
  }
  const std::string error = PathOfError(s);
  INFO(error);
  CHECK(error.rfind("gears.g1: may take part in at most 12 meshes", 0) == 0);
  s.meshes.pop_back();
  CHECK(PathOfError(s).empty());
}

// Every number of `a` equals `b`'s: the bits, since the same operations run on the same inputs.
void CheckSameMeshes(const GearTrain& a, const GearTrain& b) {
  REQUIRE(a.meshes.size() == b.meshes.size());
  CHECK(a.input_torque == b.input_torque);
  CHECK(a.body_inertia == b.body_inertia);
  CHECK(a.warnings == b.warnings);
  REQUIRE(a.topology.bodies.size() == b.topology.bodies.size());
  for (size_t i = 0; i < a.topology.bodies.size(); ++i) {
    CHECK(a.topology.bodies[i].speed == b.topology.bodies[i].speed);
  }
  for (size_t m = 0; m < a.meshes.size(); ++m) {
    const TrainMeshModel &x = a.meshes[m], &y = b.meshes[m];
    INFO(x.name);
    CHECK(x.pair.speed_a == y.pair.speed_a);
    CHECK(x.gearbox.operating.speed == y.gearbox.operating.speed);
    CHECK(x.pair.path_mesh == y.pair.path_mesh);
    CHECK(x.geometry.mesh_frequency_hz == y.geometry.mesh_frequency_hz);
    CHECK(x.geometry.mesh_period_s == y.geometry.mesh_period_s);
    CHECK(x.geometry.contact_ratio == y.geometry.contact_ratio);
    CHECK(x.transmitted_torque == y.transmitted_torque);
    CHECK(x.cycle.tau == y.cycle.tau);
    CHECK(x.cycle.load == y.cycle.load);
    REQUIRE(x.cycle.drive.size() == y.cycle.drive.size());
    for (size_t i = 0; i < x.cycle.drive.size(); ++i) {
      CHECK(x.cycle.drive[i].stiffness == y.cycle.drive[i].stiffness);
      CHECK(x.cycle.drive[i].lste == y.cycle.drive[i].lste);
      CHECK(x.cycle.back[i].stiffness == y.cycle.back[i].stiffness);
    }
    REQUIRE(x.segmentation.segments.size() == y.segmentation.segments.size());
    for (size_t j = 0; j < x.segmentation.segments.size(); ++j) {
      const MeshSegment &s = x.segmentation.segments[j], &t = y.segmentation.segments[j];
      CHECK(s.tau_begin == t.tau_begin);
      CHECK(s.tau_end == t.tau_end);
      CHECK(s.lste == t.lste);
      CHECK(s.error_weights == t.error_weights);
    }
    CHECK(x.stiffness.mean == y.stiffness.mean);
    CHECK(x.stiffness.lste_peak_to_peak == y.stiffness.lste_peak_to_peak);
  }
}

TEST_CASE("a train built at one speed and moved to another equals the train built there",
          "[train][sweep]") {
  // GearTrainAtSpeed reuses the meshes' stiffness, segmentation and torque flow: they must not
  // depend on the speed. A helical, elastic, loaded train with a loose gear, and the rigid one.
  // The excitation's amplitude changes too: a GearTrain holds none.
  for (TrainSpec spec : {testing::ElasticTwoStage(), testing::RigidTwoStage()}) {
    INFO(spec.name);
    spec.operating.excitation = {{2.0, 300.0, 0.0}};
    TrainSpec at = spec;
    at.operating.speed = 2370.0 * 2.0 * std::numbers::pi / 60.0;
    at.operating.excitation[0].amplitude = 1700.0;
    const GearTrain moved = GearTrainAtSpeed(BuildGearTrain(spec), at);
    const GearTrain built = BuildGearTrain(at);
    CheckSameMeshes(moved, built);
    // And it did move: the mesh frequencies scale with the input speed.
    const GearTrain before = BuildGearTrain(spec);
    CHECK(moved.meshes[0].geometry.mesh_frequency_hz ==
          Approx(before.meshes[0].geometry.mesh_frequency_hz * 2370.0 / 1000.0).epsilon(1e-14));
  }
}

}  // namespace
}  // namespace gearnvh
