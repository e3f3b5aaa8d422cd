// Rigid-body modes (model/modal_analysis.h): one criterion in the full FE model and every modal
// tier, so the free rotation is never listed as a natural frequency of one tier and not another,
// and a mesh far softer than the shafts it turns counts as no coupling (docs/design.md §3).
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/reduction/reduced_model.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::vector<Tier> TiersOf(const ComponentModel& m) {
  std::vector<Tier> out;
  for (Tier t : kAllTiers) {
    if (TierAvailable(m, t)) out.push_back(t);
  }
  return out;
}

double ClosestRelativeError(double f, const std::vector<double>& reference) {
  double best = 1e300;
  for (double r : reference) best = std::min(best, std::abs(f - r) / r);
  return best;
}

TEST_CASE("every tier and the full model count the free rotation alike and list no zero",
          "[reduction][rigid]") {
  // Issue 36: tiers 1-4 and N20 listed the free rotation (~2e-5 Hz, rounding) as their first
  // natural frequency, N40 full and the full model did not.
  GearboxSpec rectangular = testing::StandardPair(27, 43);
  rectangular.pinion.inertia = 3e-4;
  rectangular.wheel.inertia = 2e-3;
  rectangular.mesh.stiffness = RectangularStiffness{2e8, 3.4e8, 1.6};
  for (const GearboxSpec& spec : {rectangular, testing::FlexibleShaftsPair()}) {
    const ComponentModel m = BuildComponentModel(spec);
    const ModalSummary full = FullModelFrequencies(m, 60);
    CHECK(full.rigid_body_modes == 1);
    for (Tier tier : TiersOf(m)) {
      const ReducedModel r = ReduceModel(m, tier);
      INFO(r.name << " of a " << (m.flexible ? "flexible" : "rigid") << " pair");
      CHECK(r.rigid_body_modes == 1);
      REQUIRE_FALSE(r.natural_frequencies_hz.empty());
      // The lowest listed frequency is elastic: within 30 % of a full-model frequency (Guyan tiers
      // stiffen, none by a factor; a listed rounding zero would be 100 % off).
      CHECK(ClosestRelativeError(r.natural_frequencies_hz[0], full.frequencies_hz) < 0.3);
    }
  }
}

TEST_CASE("a mesh 1e10 times softer than the shafts it turns leaves both rotations free",
          "[reduction][rigid]") {
  // Issue 36: a 1e-3 N/m mesh between two free shafts reported 0 rigid-body modes. Its relative
  // rotation strains the shafts' torsion springs (~1e5..1e6 N m/rad, turning rigidly) and a mesh
  // spring of 1e-3 (r_b^2 ~ 1e-3): strain energy ~1e-13 of the magnitude of its terms, below the
  // 1e-10 of the criterion. Every tier and the full model must say 2.
  GearboxSpec spec = testing::FlexibleShaftsPair();
  spec.mesh.stiffness = RectangularStiffness{1e-3, 1e-3, 1.5};
  const ComponentModel m = BuildComponentModel(spec);
  CHECK(FullModelFrequencies(m, 10).rigid_body_modes == 2);
  for (Tier tier : TiersOf(m)) {
    const ReducedModel r = ReduceModel(m, tier);
    INFO(r.name);
    CHECK(r.rigid_body_modes == 2);
    if (tier != Tier::kTier1) CHECK(r.natural_frequencies_hz.front() > 10.0);
  }
}

TEST_CASE("on a bare pair the same soft mesh is the only spring its mode strains: elastic",
          "[reduction][rigid]") {
  // No shafts: the relative rotation strains the 1e-3 N/m mesh alone (no cancellation), so its
  // frequency is resolved and listed: f = (1/2 pi) sqrt(k (r_b1^2/J1 + r_b2^2/J2)) = 0.0087 Hz.
  GearboxSpec spec = testing::StandardPair(27, 43);
  spec.pinion.inertia = 3e-4;
  spec.wheel.inertia = 2e-3;
  spec.mesh.stiffness = RectangularStiffness{1e-3, 1e-3, 1.5};
  const ComponentModel m = BuildComponentModel(spec);
  const double rb1 = m.geometry.pinion.base, rb2 = m.geometry.wheel.base;
  const double f = std::sqrt(1e-3 * (rb1 * rb1 / 3e-4 + rb2 * rb2 / 2e-3)) / kTwoPi;
  const ReducedModel r = ReduceModel(m, Tier::kTier1);
  CHECK(r.rigid_body_modes == 1);
  REQUIRE(r.natural_frequencies_hz.size() == 1);
  // 1e-6: w^2 ~ 3e-3 against the shift-invert rounding eps s ~ 1e-26 and the 2x2 K's own ~1e-18.
  CHECK(r.natural_frequencies_hz[0] == Approx(f).epsilon(1e-6));
  CHECK(FullModelFrequencies(m, 10).rigid_body_modes == 1);
}

}  // namespace
}  // namespace gearnvh
