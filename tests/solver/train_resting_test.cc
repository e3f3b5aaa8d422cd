// A train that nothing presses rests (solver/train_stepper.h, TrainStaticState): without load
// every mesh starts free in the middle of its backlash and no contact event follows; an undragged
// loose gear floats beside loaded contacts; the reduced tiers alike.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "model/test_trains.h"
#include "solver/train_model.h"

namespace gearnvh {
namespace {

// The middle of mesh i's free range over its cycle, on the mean gap row (v + v_back)/2: half-way
// between its walls e_ij - b and e_ij + b at their lowest and highest.
double RestingMiddle(const TrainMeshTable& mt) {
  const auto [low, high] = std::minmax_element(mt.error.begin(), mt.error.end());
  return 0.5 * (*low + *high);
}

double RestingPlace(const TrainMeshTable& mt, const Eigen::VectorXd& z) {
  return 0.5 * (mt.v + mt.v_back).dot(z.head(mt.v.size()));
}

// Asserts that every mesh of `t` starts free in the middle of its backlash and that a run of
// `cycles` cycles of the first mesh has no contact event, no grazing and no switch at a grid
// segment's start, and leaves every mesh where it was.
void RequireRests(const TrainTables& t, double cycles) {
  const auto [z0, states0] = TrainStaticState(t);
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    INFO("mesh " << t.meshes[i].name);
    CHECK(states0[i] == ContactState::kFree);
    // The place is computed from angles of ~b / r_b: its rounding is ~1e-16 b, 1e-12 b is far
    // above it and far below any misplacement (the least-norm place was off by microns).
    CHECK(std::abs(RestingPlace(t.meshes[i], z0) - RestingMiddle(t.meshes[i])) <=
          1e-12 * t.meshes[i].half_backlash);
  }
  TrainStepper stepper(t, {}, z0, states0);
  REQUIRE(stepper.Run(cycles * t.meshes.front().period));
  const TrainStepperSummary s = stepper.summary();
  // No force acts on any body (no load, no excitation, every contact open), so the exact solution
  // is constant: the bound on contact events is 0, not a count that rounding may reach.
  CHECK(s.events == 0);
  CHECK(s.grazing == 0);
  CHECK(s.start_switches == 0);
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    CHECK(stepper.states()[i] == ContactState::kFree);
    CHECK(std::abs(RestingPlace(t.meshes[i], stepper.state()) - RestingPlace(t.meshes[i], z0)) <=
          1e-12 * t.meshes[i].half_backlash);
  }
}

TEST_CASE("train static state: without load every mesh rests free in its backlash at any speed",
          "[solver][train]") {
  // The small rattler without its loads and engine order, at six speeds over the default sweep's
  // 500-6000 rpm (app/train_resting_test.cc runs all 56 on the manual transmission; each speed
  // here builds its tables, ~1 s). Its loose gear's mesh carries an unloaded error (20 um and 10 um
  // at the first two mesh harmonics): the walls move from segment to segment, and the middle of
  // their range (not delta = 0) keeps the gear about 27 um from both. Before, each contact of the
  // static solve sat exactly on its wall at zero force and rounding chose its state: the manual
  // transmission started with a loose gear 61 um beyond a wall (hundreds of impacts) or grazed a
  // zero-force contact 1001 times in one grid segment.
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.operating.loads.clear();
  spec.meshes[1].mesh.static_transmission_error = {{20e-6, 10e-6}, {0.0, 0.0}};
  for (int rpm = 500; rpm <= 6000; rpm += 1100) {
    INFO(rpm << " rpm");
    spec.operating.speed = rpm * 2.0 * std::numbers::pi / 60.0;
    const testing::TrainModel model(spec);
    const TrainMeshTable& loose = model.tables.meshes[1];
    const auto [low, high] = std::minmax_element(loose.error.begin(), loose.error.end());
    REQUIRE(*high - *low > 20e-6);  // the walls do move
    RequireRests(model.tables, 50.0);
  }
}

TEST_CASE("train static state: an undragged loose gear floats in the middle beside loaded contacts",
          "[solver][train]") {
  // The rattler with its layshaft load but no drag on the loose gear g4 and no engine order: the
  // loaded mesh g1-g2 is pressed on its drive flank; g3-g4 carries no force, so it is free, in the
  // middle of its backlash (moving g4 alone moves no loaded contact), and stays free while the
  // layshaft vibrates under the varying mesh stiffness (TE variation well below a micron against
  // the 50 um half backlash).
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.operating.loads = {{"layshaft", 20.0}};
  const testing::TrainModel model(spec);
  const TrainTables& t = model.tables;
  const auto [z0, states0] = TrainStaticState(t);
  REQUIRE(states0 == std::vector<ContactState>{ContactState::kDrive, ContactState::kFree});
  // Pressed by 20 N m over a base radius of ~19 mm and k ~ 1e8-1e9 N/m: ~1e-7 m.
  CHECK(t.GapValue(0, 0, true, z0) > 1e-9);
  CHECK(std::abs(RestingPlace(t.meshes[1], z0) - RestingMiddle(t.meshes[1])) <=
        1e-12 * t.meshes[1].half_backlash);
  TrainStepper stepper(t, {}, z0, states0);
  REQUIRE(stepper.Run(200.0 * t.meshes.front().period));
  CHECK(stepper.summary().events == 0);
  CHECK(stepper.summary().grazing == 0);
  CHECK(stepper.states() == states0);
}

TEST_CASE("train static state: without load the reduced tiers rest too", "[solver][train][tiers]") {
  // The elastic two-stage train (bearings, an elastic layshaft and output, a loose gear) without
  // its loads: from tier 2 on the back flank's gap row differs from the drive flank's, and the
  // place is taken on their mean.
  TrainSpec spec = testing::ElasticTwoStage();
  spec.operating.loads.clear();
  const GearTrain train = BuildGearTrain(spec);
  for (Tier tier : {Tier::kTier2, Tier::kTier3}) {
    INFO("tier " << static_cast<int>(tier) + 1);
    RequireRests(BuildTrainTablesAtTier(spec, train, tier), 20.0);
  }
}

}  // namespace
}  // namespace gearnvh
