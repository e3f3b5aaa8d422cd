#include "gearnvh/reduction/tier_adequacy.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "model/test_specs.h"

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

}  // namespace
}  // namespace gearnvh
