// The atlas of a gear train (analysis/include/gearnvh/analysis/train_atlas.h): cells that differ
// only in input speed or excitation amplitude share their meshes (built once, moved to each cell);
// every cell must be the cell a fresh build gives.
#include "gearnvh/analysis/train_atlas.h"

#include <catch2/catch.hpp>
#include <numbers>

#include "config/gearbox_loader.h"
#include "gearnvh/model/spec_parameters.h"
#include "loose_gear_train_yaml.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

using testing::kRpm;  // rad/s per rpm

// Each cell of `atlas` equals ComputeTrainAtlasPoint on its variant built from scratch: the same
// operations on the same bits (GearTrainAtSpeed equals BuildGearTrain), so equal to the bit.
void CheckCellsAreFreshBuilds(const TrainSpec& base, const TrainAtlasResult& atlas,
                              const TrainAtlasOptions& options) {
  REQUIRE(atlas.cells.size() == 6);
  for (const TrainAtlasCell& c : atlas.cells) {
    INFO("cell " << c.ix << ", " << c.iy);
    TrainSpec variant = base;
    SetTrainParameter(variant, atlas.x.parameter, c.x, "x");
    SetTrainParameter(variant, atlas.y.parameter, c.y, "y");
    const TrainAtlasPoint fresh = ComputeTrainAtlasPoint(variant, options);
    INFO(c.point.message << fresh.message);
    REQUIRE(c.point.ok);
    REQUIRE(fresh.ok);
    CHECK(c.point.lyapunov_per_s == fresh.lyapunov_per_s);
    CHECK(c.point.regime == fresh.regime);
    REQUIRE(c.point.meshes.size() == fresh.meshes.size());
    for (size_t m = 0; m < fresh.meshes.size(); ++m) {
      CHECK(c.point.meshes[m].drive_impacts_per_cycle == fresh.meshes[m].drive_impacts_per_cycle);
      CHECK(c.point.meshes[m].back_impacts_per_cycle == fresh.meshes[m].back_impacts_per_cycle);
      CHECK(c.point.meshes[m].impact_velocity_rms == fresh.meshes[m].impact_velocity_rms);
    }
    REQUIRE(c.point.loose_gears.size() == fresh.loose_gears.size());
    for (size_t g = 0; g < fresh.loose_gears.size(); ++g) {
      CHECK(c.point.loose_gears[g].rattle_index == fresh.loose_gears[g].rattle_index);
    }
  }
}

TEST_CASE(
    "a train atlas shares meshes across speeds and amplitudes and gives the cells of fresh builds",
    "[app][train][atlas]") {
  // The rattling three-mesh train: speed x drag torque on its loose gear (the mesh loads change
  // with the drag, so each drag value is its own build), speed on either axis, two threads.
  const config::LoadedGearbox loaded =
      config::LoadAnyGearboxFromString(testing::kLooseGearTrainYaml, "loose_gear_train.yaml");
  const AtlasAxis speed{"operating.speed", {900.0 * kRpm, 1100.0 * kRpm, 3}};
  const AtlasAxis drag{"operating.loads[1].torque", {0.1, 0.3, 2}};
  TrainAtlasOptions options;
  options.cycles = 40;
  options.transient_cycles = 10;
  SECTION("speed on x") {
    const TrainAtlasResult atlas = RunTrainAtlas(loaded.train, speed, drag, options, 2);
    CheckCellsAreFreshBuilds(loaded.train, atlas, options);
  }
  SECTION("speed on y") {
    const TrainAtlasResult atlas = RunTrainAtlas(loaded.train, drag, speed, options, 2);
    CheckCellsAreFreshBuilds(loaded.train, atlas, options);
  }
  SECTION("speed x excitation amplitude: one build for every cell") {
    const AtlasAxis amplitude{"operating.excitation[0].amplitude", {500.0, 1500.0, 2}};
    const TrainAtlasResult atlas = RunTrainAtlas(loaded.train, speed, amplitude, options, 2);
    CheckCellsAreFreshBuilds(loaded.train, atlas, options);
  }
  SECTION("excitation amplitude x drag") {
    const AtlasAxis amplitude{"operating.excitation[0].amplitude", {500.0, 1000.0, 3}};
    const TrainAtlasResult atlas = RunTrainAtlas(loaded.train, amplitude, drag, options, 2);
    CheckCellsAreFreshBuilds(loaded.train, atlas, options);
  }
}

}  // namespace
}  // namespace gearnvh
