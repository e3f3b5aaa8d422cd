#include "gearnvh/reduction/tier_adequacy.h"

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "model/test_specs.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

double ThreeTimesMesh(const GearboxSpec& spec) {
  return 3.0 * spec.pinion.teeth * spec.operating.speed / (2.0 * std::numbers::pi);
}

TEST_CASE("tier 1 is adequate for a rigid pair until the gears' lateral modes enter the range",
          "[reduction][adequacy]") {
  GearboxSpec spec = testing::StandardPair(27, 43);
  spec.operating.torque = 20.0;
  for (auto [rpm, adequate] : {std::pair{800.0, true}, {9000.0, false}}) {
    spec.operating.speed = rpm * 2 * std::numbers::pi / 60;
    const ComponentModel model = BuildComponentModel(spec);
    TierAdequacyOptions options;
    options.max_frequency_hz = ThreeTimesMesh(spec);
    const MeshModes full = FullModelMeshModes(model, options);
    const TierAdequacy a =
        AssessTierAdequacy(model, ReduceModel(model, Tier::kTier1), full, options);
    INFO(rpm << " rpm, limit " << options.max_frequency_hz << " Hz: " << a.Warning());
    CHECK(a.adequate == adequate);
    if (!adequate) {
      // The lateral modes along the line of action need the translations of tier 2.
      REQUIRE(a.adequate_tier.has_value());
      CHECK(*a.adequate_tier == Tier::kTier2);
      CHECK(a.Warning().find("tier 2 reproduces") != std::string::npos);
      CHECK(AssessTierAdequacy(model, ReduceModel(model, Tier::kTier2), full, options).adequate);
    } else {
      CHECK(a.Warning().empty());
    }
  }
}

GearboxSpec FlexiblePair() {
  GearboxSpec spec = testing::FlexibleShaftsPair(0.01);
  spec.operating.speed = 3000.0 * 2 * std::numbers::pi / 60;
  return spec;
}

TEST_CASE("on flexible shafts the rigid tiers miss the shaft modes the mesh sees, N40 does not",
          "[reduction][adequacy]") {
  const GearboxSpec spec = FlexiblePair();
  const ComponentModel model = BuildComponentModel(spec);
  TierAdequacyOptions options;
  options.max_frequency_hz = ThreeTimesMesh(spec);
  const MeshModes full = FullModelMeshModes(model, options);
  REQUIRE(!full.frequencies_hz.empty());
  const TierAdequacy t1 =
      AssessTierAdequacy(model, ReduceModel(model, Tier::kTier1), full, options);
  INFO(t1.Warning());
  CHECK_FALSE(t1.adequate);
  REQUIRE(t1.adequate_tier.has_value());
  // The named tier is adequate when assessed itself.
  CHECK(AssessTierAdequacy(model, ReduceModel(model, *t1.adequate_tier), full, options).adequate);
  CHECK(AssessTierAdequacy(model, ReduceModel(model, Tier::kTier5), full, options).adequate);
}

TEST_CASE("the sparse and dense full-model solves give the same mesh modes",
          "[reduction][adequacy]") {
  const ComponentModel model = BuildComponentModel(FlexiblePair());
  TierAdequacyOptions options;
  options.max_frequency_hz = 5000.0;
  const MeshModes dense = FullModelMeshModes(model, options);
  options.dense_limit = 0;  // force Spectra's shift-invert Lanczos
  const MeshModes sparse = FullModelMeshModes(model, options);
  REQUIRE(dense.frequencies_hz.size() == sparse.frequencies_hz.size());
  for (size_t i = 0; i < dense.frequencies_hz.size(); ++i) {
    // Lanczos tolerance 1e-10 on eigenvalues: 1e-8 on frequencies is ample. Shares depend on the
    // modes summed (all n for dense, 60 for sparse): equal to the modes' own weight, 2 %.
    CHECK(sparse.frequencies_hz[i] == Approx(dense.frequencies_hz[i]).epsilon(1e-8));
    CHECK(sparse.shares[i] == Approx(dense.shares[i]).epsilon(0.02));
  }
}

TEST_CASE("a mode matters when some mesh sees it: the largest of the meshes' shares",
          "[reduction][adequacy]") {
  // Three unit-mass modes at 100, 200, 300 Hz (identity shapes) and two meshes: mesh 0 sees modes
  // 1 and 2 equally (v = [1, 1, 0]), mesh 1 sees modes 2 and 3 (v = [0, 1, 1]). Mesh 0's shares
  // are (1/w1^2, 1/w2^2) / (1/w1^2 + 1/w2^2) = 4/5, 1/5; mesh 1's are 9/13, 4/13 (closed form).
  NaturalModes modes;
  modes.frequencies_hz = {100.0, 200.0, 300.0};
  modes.shapes = Eigen::MatrixXd::Identity(3, 3);
  TierAdequacyOptions options;
  options.max_frequency_hz = 1000.0;
  const std::vector<Eigen::VectorXd> meshes{Eigen::Vector3d(1, 1, 0), Eigen::Vector3d(0, 1, 1)};
  const MeshModes seen = MeshSeenModes(modes, meshes, {1000.0, 1000.0}, options);
  REQUIRE(seen.frequencies_hz.size() == 3);
  // Shares are ratios of a few products: 1e-14 relative.
  CHECK(seen.shares[0] == Approx(4.0 / 5.0).epsilon(1e-14));
  CHECK(seen.mesh[0] == 0);
  CHECK(seen.shares[1] == Approx(9.0 / 13.0).epsilon(1e-14));  // mesh 1's 9/13 beats mesh 0's 1/5
  CHECK(seen.mesh[1] == 1);
  CHECK(seen.shares[2] == Approx(4.0 / 13.0).epsilon(1e-14));
  CHECK(seen.mesh[2] == 1);
  // A share under min_share does not count: at 0.75 only mode 1 (4/5) is left.
  options.min_share = 0.75;
  CHECK(MeshSeenModes(modes, meshes, {1000.0, 1000.0}, options).frequencies_hz ==
        std::vector<double>{100.0});
  // Each mesh up to its own limit: mesh 1 excites nothing above 150 Hz, so mode 2 is mesh 0's
  // (1/5) and mode 3 is nobody's; mesh 1's shares stay over every computed mode.
  options.min_share = 0.01;
  const MeshModes own = MeshSeenModes(modes, meshes, {1000.0, 150.0}, options);
  REQUIRE(own.frequencies_hz == std::vector<double>{100.0, 200.0});
  CHECK(own.mesh == std::vector<int>{0, 0});
  CHECK(own.shares[1] == Approx(1.0 / 5.0).epsilon(1e-14));
}

TEST_CASE("a schema-1 pair's train gets the pair's tier verdict from its own structure",
          "[reduction][adequacy][train]") {
  // The ComponentModel and the TrainStructure of TrainOf(pair) are built by separate code; the
  // same FE model gives the same modes and the same verdict at every tier.
  const GearboxSpec spec = FlexiblePair();
  const ComponentModel model = BuildComponentModel(spec);
  const TrainSpec train_spec = TrainOf(spec);
  const GearTrain train = BuildGearTrain(train_spec);
  const TrainStructure structure = AssembleTrainStructure(train_spec, train);
  TierAdequacyOptions options;
  options.max_frequency_hz = ThreeTimesMesh(spec);
  const MeshModes pair_modes = FullModelMeshModes(model, options);
  const MeshModes train_modes = FullModelMeshModes(structure, {options.max_frequency_hz}, options);
  CHECK(train_modes.complete);
  REQUIRE(train_modes.frequencies_hz.size() == pair_modes.frequencies_hz.size());
  for (size_t i = 0; i < pair_modes.frequencies_hz.size(); ++i) {
    // Two assemblies and eigen-solves of one model (the train removes its free rotation by
    // projection, the pair by the zero test): 1e-8 on frequencies; shares sum over slightly
    // different sets of modes (the pair's count includes the free rotation's slot): 1e-6.
    CHECK(train_modes.frequencies_hz[i] == Approx(pair_modes.frequencies_hz[i]).epsilon(1e-8));
    CHECK(train_modes.shares[i] == Approx(pair_modes.shares[i]).epsilon(1e-6));
    CHECK(train_modes.mesh[i] == 0);
  }
  for (Tier tier : {Tier::kTier1, Tier::kTier3, Tier::kTier5, Tier::kN20Mta}) {
    CAPTURE(TierName(tier));
    const TierAdequacy p = AssessTierAdequacy(model, ReduceModel(model, tier), pair_modes, options);
    const TierAdequacy t =
        AssessTierAdequacy(structure, ReduceTrain(structure, tier), train_modes, options);
    CHECK(t.adequate == p.adequate);
    CHECK(t.adequate_tier == p.adequate_tier);
    CHECK(t.Warning() == p.Warning());
  }
}

// The elastic two-stage train (model/test_trains.h), its mesh models and its full structure.
struct TwoStageModel {
  TrainSpec spec = testing::ElasticTwoStage();
  GearTrain train = BuildGearTrain(spec);
  TrainStructure structure = AssembleTrainStructure(spec, train);
};

TEST_CASE("a train's tier check names the mesh that sees the missed mode and a tier that has it",
          "[reduction][adequacy][train]") {
  const TwoStageModel model;
  const TrainSpec& spec = model.spec;
  const GearTrain& train = model.train;
  const TrainStructure& structure = model.structure;
  TierAdequacyOptions options;
  std::vector<double> limits;
  for (const TrainMeshModel& m : train.meshes) limits.push_back(3.0 * m.geometry.mesh_frequency_hz);
  options.max_frequency_hz = *std::max_element(limits.begin(), limits.end());
  const MeshModes full = FullModelMeshModes(structure, limits, options);
  REQUIRE_FALSE(full.frequencies_hz.empty());
  CHECK(full.complete);
  // Each mode is within the limit of the mesh that sees it.
  for (size_t i = 0; i < full.frequencies_hz.size(); ++i) {
    CHECK(full.frequencies_hz[i] <= limits[static_cast<size_t>(full.mesh[i])]);
  }
  std::vector<std::string> names;
  for (const TrainMesh& m : spec.meshes) names.push_back(m.Name());
  const TierAdequacy t1 =
      AssessTierAdequacy(structure, ReduceTrain(structure, Tier::kTier1), full, options);
  INFO(t1.Warning(names));
  REQUIRE_FALSE(t1.adequate);
  // The warning names the mesh that sees the worst missed mode (the largest share not
  // reproduced), and the tier it recommends passes its own check.
  const TierModeMatch* worst = nullptr;
  for (const TierModeMatch& m : t1.modes) {
    if (!m.reproduced && (worst == nullptr || m.share > worst->share)) worst = &m;
  }
  REQUIRE(worst != nullptr);
  CHECK(t1.Warning(names).find("compliance of mesh " + names[static_cast<size_t>(worst->mesh)]) !=
        std::string::npos);
  REQUIRE(t1.adequate_tier.has_value());
  CHECK(AssessTierAdequacy(structure, ReduceTrain(structure, *t1.adequate_tier), full, options)
            .adequate);
  // Tier 5 keeps 14 shaft modes per elastic shaft: it reproduces every mode below the limit here.
  CHECK(
      AssessTierAdequacy(structure, ReduceTrain(structure, Tier::kTier5), full, options).adequate);
  // Every mode the meshes see is seen by one of the three meshes.
  for (int m : full.mesh) CHECK((m >= 0 && m < 3));
}

TEST_CASE("a train's sparse and dense full-model solves give the same mesh modes",
          "[reduction][adequacy][train]") {
  // Above dense_limit the train's modes come from Lanczos, which drops the free rotation as its
  // lowest eigenpair instead of projecting it out; a limit above the first sparse_modes (8 here)
  // makes it ask for more (the count doubles until the modes pass the limit).
  const TwoStageModel model;
  const TrainSpec& spec = model.spec;
  const TrainStructure& structure = model.structure;
  TierAdequacyOptions options;
  options.max_frequency_hz = 20000.0;
  options.sparse_modes = 8;
  const std::vector<double> limits(spec.meshes.size(), options.max_frequency_hz);
  const MeshModes dense = FullModelMeshModes(structure, limits, options);
  options.dense_limit = 0;
  const MeshModes sparse = FullModelMeshModes(structure, limits, options);
  CHECK(dense.complete);
  CHECK(sparse.complete);
  CHECK(sparse.found_up_to_hz >= options.max_frequency_hz);
  REQUIRE(dense.frequencies_hz.size() == sparse.frequencies_hz.size());
  for (size_t i = 0; i < dense.frequencies_hz.size(); ++i) {
    // Lanczos tolerance 1e-10 on eigenvalues: 1e-8 on frequencies.
    CHECK(sparse.frequencies_hz[i] == Approx(dense.frequencies_hz[i]).epsilon(1e-8));
    CHECK(sparse.mesh[i] == dense.mesh[i]);
    // A share is over the modes computed: the sparse solve leaves out those above the ones it
    // found, so each mesh's shares are its dense ones times one factor (dense total / sparse
    // total, the same for every mode: 1e-6), >= 1 and here within 5 % (the modes left out are far
    // above the meshes' frequencies and hold little compliance).
    const double factor = sparse.shares[i] / dense.shares[i];
    const size_t first = static_cast<size_t>(
        std::find(dense.mesh.begin(), dense.mesh.end(), dense.mesh[i]) - dense.mesh.begin());
    CHECK(factor == Approx(sparse.shares[first] / dense.shares[first]).epsilon(1e-6));
    CHECK(factor >= 1.0 - 1e-12);
    CHECK(factor <= 1.05);
  }
}

}  // namespace
}  // namespace gearnvh
