// Tier 1 against the closed form f = (1/2 pi) sqrt(k_bar (r_b1^2/J1 + r_b2^2/J2)) under a
// rectangular stiffness override, whose k_bar = single + (double - single)(contact_ratio - 1) is
// exact (docs/design.md §2.3): the pair of issue 36's probe and a two-stage train.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/reduction/reduced_model.h"
#include "model/test_specs.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

constexpr double kRadPerCycle = 2.0 * std::numbers::pi;

// single 2e8, double 3.4e8 N/m, contact ratio 1.6: k_bar = 2.84e8 N/m.
RectangularStiffness Rectangular(double contact_ratio = 1.6) {
  return RectangularStiffness{2e8, 3.4e8, contact_ratio};
}
double MeanOf(const RectangularStiffness& r) {
  return r.single + (r.double_pair - r.single) * (r.contact_ratio - 1.0);
}

// Base radius of a standard gear: m z cos(alpha0) / 2.
double BaseRadius(int teeth, double module) {
  return 0.5 * module * teeth * std::cos(20.0 * std::numbers::pi / 180.0);
}

TEST_CASE("tier 1 of a rigid pair with a rectangular override is the closed form",
          "[reduction][closed_form]") {
  // 27/43 teeth, module 2 mm, 20 deg, J 3e-4 and 2e-3 kg m^2. A sampled cycle mean (2048
  // midpoints, 1229 of them before the switch at 0.6) put k_bar 4.8e-5 and f 2.4e-5 high.
  GearboxSpec spec = testing::StandardPair(27, 43);
  spec.pinion.inertia = 3e-4;
  spec.wheel.inertia = 2e-3;
  spec.mesh.stiffness = Rectangular();
  const ComponentModel m = BuildComponentModel(spec);
  const double k = MeanOf(Rectangular());
  // 1e-12: the segment sum adds 32 products, a few roundings each.
  CHECK(m.mesh_summary.mean == Approx(k).epsilon(1e-12));
  const double rb1 = BaseRadius(27, 2e-3), rb2 = BaseRadius(43, 2e-3);
  const double f = std::sqrt(k * (rb1 * rb1 / 3e-4 + rb2 * rb2 / 2e-3)) / kRadPerCycle;
  const ReducedModel r = ReduceModel(m, Tier::kTier1);
  REQUIRE(r.natural_frequencies_hz.size() == 1);
  CHECK(r.rigid_body_modes == 1);
  // 1e-9 (the bar): a 2x2 eigenproblem in shift-invert form, rounding ~1e-15.
  CHECK(r.natural_frequencies_hz[0] == Approx(f).epsilon(1e-9));
  CHECK(f == Approx(4616.1405).epsilon(1e-8));  // the probe's independent value
}

TEST_CASE("tier 1 of a two-stage train with rectangular overrides is the closed form",
          "[reduction][closed_form][train]") {
  // Input (g1 20) -> layshaft (g2 40, g3 20) -> output (g4 40); every gear's inertia given so the
  // bodies' inertias are shaft + gears (docs/gear-trains.md, "Inertias").
  TrainSpec t = testing::TwoStageTrain(150.0, 0.0, 600.0);
  t.operating.excitation.clear();
  const double gear_j[4] = {1e-4, 6e-4, 2e-4, 8e-4};
  for (int g = 0; g < 4; ++g) t.gears[static_cast<size_t>(g)].gear.inertia = gear_j[g];
  const RectangularStiffness first = Rectangular(1.6), second = Rectangular(1.45);
  t.meshes[0].mesh.stiffness = first;
  t.meshes[1].mesh.stiffness = second;
  const GearTrain train = BuildGearTrain(t);
  const double j_in = 2e-3 + gear_j[0], j_lay = 1e-3 + gear_j[1] + gear_j[2],
               j_out = 5e-3 + gear_j[3];
  const double ra = BaseRadius(20, 2e-3), rb = BaseRadius(40, 2e-3);
  // Nonzero eigenvalues of M^-1 K, K = sum k_i v_i v_i^T, are those of the 2x2 diag(k) V^T M^-1 V
  // (V = [v1 v2]): lambda = (p + q)/2 +- sqrt(((p - q)/2)^2 + k1 k2 c^2).
  const double k1 = MeanOf(first), k2 = MeanOf(second);
  const double p = k1 * (ra * ra / j_in + rb * rb / j_lay), q = k2 * (ra * ra / j_lay + rb * rb / j_out);
  const double c = rb * ra / j_lay;
  const double root = std::sqrt(0.25 * (p - q) * (p - q) + k1 * k2 * c * c);
  const double f_low = std::sqrt(0.5 * (p + q) - root) / kRadPerCycle;
  const double f_high = std::sqrt(0.5 * (p + q) + root) / kRadPerCycle;
  const TrainTorsionalModes modes = TorsionalModes(train);
  CHECK(modes.free_rotations == 1);
  REQUIRE(modes.frequencies_hz.size() == 2);
  // 1e-9: 3x3 dense eigenproblem, rounding ~1e-14 of the largest eigenvalue.
  CHECK(modes.frequencies_hz[0] == Approx(f_low).epsilon(1e-9));
  CHECK(modes.frequencies_hz[1] == Approx(f_high).epsilon(1e-9));
}

}  // namespace
}  // namespace gearnvh
