// Campbell data of a gear train (nvh/train_campbell.h): order lines of every shaft and mesh, and
// critical speeds at the crossings with the torsional modes of tier 1 (closed form: a mode f_n
// that does not move with speed meets the line of order o at input speed 2 pi f_n / o).
#include "gearnvh/nvh/train_campbell.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "model/test_trains.h"

namespace gearnvh {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

TEST_CASE("a train's order lines are its shafts' speeds and its mesh harmonics",
          "[campbell][train]") {
  const TrainSpec spec = testing::RigidTwoStage();
  const GearTrain train = BuildGearTrain(spec);
  const std::vector<OrderLine> lines = TrainOrderLines(spec, train);
  REQUIRE(lines.size() == 3 + 3 * 3);
  // input 1, layshaft 20/40, output 20/40 * 18/54; mesh g1-g2 order 20 h; g3-g4 18 * 1/2 h;
  // g6-g5 25 * 1/2 h (exact ratios of teeth: 1e-15).
  CHECK(lines[0].order == Approx(1.0).epsilon(1e-15));
  CHECK(lines[1].order == Approx(0.5).epsilon(1e-15));
  CHECK(lines[2].order == Approx(0.5 * 18.0 / 54.0).epsilon(1e-15));
  CHECK(lines[3].label == "mesh g1-g2 1x");
  CHECK(lines[4].order == Approx(40.0).epsilon(1e-15));
  CHECK(lines[6].order == Approx(9.0).epsilon(1e-15));
  CHECK(lines[11].order == Approx(37.5).epsilon(1e-15));
}

TEST_CASE("mesh harmonics of one order share a line, named by both", "[campbell][train]") {
  // g3 (30 teeth) on the layshaft at 20/30 of the input speed meshes at order 30 x 2/3 = 20 of
  // the input, as g1 (20) does: harmonics 1-3 of both meshes coincide (to rounding of the ratio).
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.gears[2].gear.teeth = 30;  // g3; g4 keeps the centre distance of g1-g2 (20 + 30)
  spec.gears[3].gear.teeth = 20;
  const GearTrain train = BuildGearTrain(spec);
  const std::vector<OrderLine> lines = TrainOrderLines(spec, train);
  REQUIRE(lines.size() == 2 + 3);  // input 1x, layshaft 1x, three joined mesh lines
  CHECK(lines[2].label == "mesh g1-g2 1x = mesh g3-g4 1x");
  CHECK(lines[4].label == "mesh g1-g2 3x = mesh g3-g4 3x");
  CHECK(lines[4].order == Approx(60.0).epsilon(1e-15));
  // Shafts at one speed to rounding share a line too: the output behind 20/30 and 30/20 turns at
  // the input's speed, multiplied stage by stage (at 1500 rpm that gives 1 - 2e-16 of it).
  TrainSpec back = testing::RigidTwoStage();
  back.operating.speed = 1500.0 * kTwoPi / 60.0;
  back.gears[1].gear.teeth = 30;  // g2 on the layshaft
  back.gears[2].gear.teeth = 30;  // g3 on the layshaft
  back.gears[3].gear.teeth = 20;  // g4 on the output
  // g6-g5 keeps the centre distance of g3-g4 (30 + 20 teeth of 2 mm).
  back.gears[4].gear.module = back.gears[5].gear.module = 2e-3 * 50.0 / 55.0;
  const GearTrain back_train = BuildGearTrain(back);
  const std::vector<OrderLine> back_lines = TrainOrderLines(back, back_train);
  CHECK(back_lines[0].label == "input, output 1x");
  CHECK(back_lines[1].label == "layshaft 1x");
}

TEST_CASE("train Campbell at tier 1: constant torsional modes crossed by every order line",
          "[campbell][train]") {
  TrainSpec spec = testing::RigidTwoStage();
  for (TrainMesh& m : spec.meshes) m.mesh.damping_ratio = 0.0;  // undamped: f = TorsionalModes'
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  const TrainReducedModel tier1 = ReduceTrain(structure, Tier::kTier1);
  const TrainTorsionalModes modes = TorsionalModes(train);
  std::vector<double> speeds;
  for (int i = 0; i <= 40; ++i) speeds.push_back(kTwoPi * (100.0 + 150.0 * i) / 60.0);
  CampbellOptions options;
  options.max_frequency_hz = 2.0 * modes.frequencies_hz.back();
  const CampbellData data = TrainCampbell(spec, train, structure, tier1, speeds, options);
  REQUIRE(data.modes.size() == modes.frequencies_hz.size());
  for (size_t k = 0; k < data.modes.size(); ++k) {
    CHECK(data.modes[k].type == ModeType::kTorsional);
    for (double f : data.frequency_hz[k]) {
      // No gyroscopics and no damping at tier 1: the undamped torsional frequencies (1e-6: the
      // first-order eigensolver against the projected symmetric one).
      CHECK(f == Approx(modes.frequencies_hz[k]).epsilon(1e-6));
    }
  }
  // Every crossing inside the sweep, and only those, at the closed-form speed.
  const std::vector<OrderLine> lines = TrainOrderLines(spec, train);
  size_t expected = 0;
  for (size_t k = 0; k < modes.frequencies_hz.size(); ++k) {
    for (const OrderLine& line : lines) {
      const double w = kTwoPi * modes.frequencies_hz[k] / line.order;
      if (w > speeds.front() && w < speeds.back()) ++expected;
    }
  }
  CHECK(data.critical_speeds.size() == expected);
  REQUIRE(expected > 0);
  for (const CriticalSpeed& c : data.critical_speeds) {
    double order = 0.0;
    for (const OrderLine& line : lines) {
      if (line.label == c.order) order = line.order;
    }
    // A constant mode and a straight line: linear interpolation is exact (1e-6 from the frequency).
    CHECK(c.speed_rad_s ==
          Approx(kTwoPi * modes.frequencies_hz[static_cast<size_t>(c.mode)] / order).epsilon(1e-6));
  }
}

}  // namespace
}  // namespace gearnvh
