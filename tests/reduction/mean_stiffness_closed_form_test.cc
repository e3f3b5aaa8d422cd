// Tier 1 against closed forms built from the inputs alone (issue 36): with a rectangular
// override the mean mesh stiffness is exactly k = single (2 - eps) + double (eps - 1), and the
// rigid torsional modes follow from k, the base radii r_b = m z cos(alpha) / 2 and the inertias.
// The model's k is the cycle mean of the segments the solver integrates (docs/design.md), which
// is exact for an override, so the frequencies must agree to rounding.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/reduction/train_reduction.h"
#include "model/test_trains.h"

namespace gearnvh {
namespace {

const RectangularStiffness kOverride{2e8, 3.4e8, 1.6};

double ExactMean(const RectangularStiffness& r) {
  return r.single * (2.0 - r.contact_ratio) + r.double_pair * (r.contact_ratio - 1.0);
}

double Hertz(double omega_squared) { return std::sqrt(omega_squared) / (2.0 * std::numbers::pi); }

double BaseRadius(double module, int teeth) {
  return 0.5 * module * teeth * std::cos(20.0 * std::numbers::pi / 180.0);
}

TEST_CASE("tier 1 of a rigid pair with a rectangular override meets the closed form",
          "[reduction][closed-form]") {
  GearboxSpec spec = testing::StandardPair(27, 43);
  spec.pinion.inertia = 3e-4;
  spec.wheel.inertia = 2e-3;
  spec.mesh.stiffness = kOverride;
  const ComponentModel m = BuildComponentModel(spec);
  const double rb1 = BaseRadius(2e-3, 27), rb2 = BaseRadius(2e-3, 43);
  const double k = ExactMean(kOverride);                              // 2.84e8 N/m
  const double f = Hertz(k * (rb1 * rb1 / 3e-4 + rb2 * rb2 / 2e-3));  // 4616.14 Hz
  CHECK(m.mesh_summary.mean == Approx(k).epsilon(1e-14));
  const ReducedModel r = ReduceModel(m, Tier::kTier1);
  REQUIRE(r.natural_frequencies_hz.size() == 1);
  // 1e-9 (the bound): the 2x2 eigenproblem rounds at ~1e-15; the sampled mean was 4.8e-5
  // high (2.4e-5 in f).
  CHECK(r.natural_frequencies_hz[0] == Approx(f).epsilon(1e-9));
}

TEST_CASE("tier 1 of a rigid two-stage train with rectangular overrides meets the closed form",
          "[reduction][train][closed-form]") {
  // Input (g1, 20) -> layshaft (g2, 40; g3, 20) -> output (g4, 40), every gear's inertia given.
  // With a_g = r_b,g / sqrt(J_body), u1 = (a_g1, a_g2, 0), u2 = (0, a_g3, a_g4), the mass-scaled
  // stiffness k1 u1 u1^T + k2 u2 u2^T has rank 2: its nonzero eigenvalues are those of the Gram
  // matrix [[k1 |u1|^2, s], [s, k2 |u2|^2]], s = sqrt(k1 k2) u1.u2 (mesh senses only flip signs).
  TrainSpec spec = testing::TwoStageTrain(150.0, 0.0, 600.0);
  const double gear_inertia[] = {1e-4, 6e-4, 2e-4, 9e-4};
  for (size_t g = 0; g < 4; ++g) spec.gears[g].gear.inertia = gear_inertia[g];
  const RectangularStiffness second{1.5e8, 2.7e8, 1.45};
  spec.meshes[0].mesh.stiffness = kOverride;
  spec.meshes[1].mesh.stiffness = second;
  ValidateTrainSpec(spec);
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  const double j_in = 2e-3 + 1e-4, j_lay = 1e-3 + 6e-4 + 2e-4, j_out = 5e-3 + 9e-4;
  const double a1 = BaseRadius(2e-3, 20) / std::sqrt(j_in),
               a2 = BaseRadius(2e-3, 40) / std::sqrt(j_lay);
  const double a3 = BaseRadius(2e-3, 20) / std::sqrt(j_lay),
               a4 = BaseRadius(2e-3, 40) / std::sqrt(j_out);
  const double k1 = ExactMean(kOverride), k2 = ExactMean(second);
  const double p = k1 * (a1 * a1 + a2 * a2), q = k2 * (a3 * a3 + a4 * a4);
  const double s2 = k1 * k2 * (a2 * a3) * (a2 * a3);
  const double trace = p + q, det = p * q - s2;
  const double root = std::sqrt(trace * trace - 4.0 * det);
  const double f_low = Hertz(2.0 * det / (trace + root));  // cancellation-free
  const double f_high = Hertz(0.5 * (trace + root));
  const TrainReducedModel r = ReduceTrain(structure, Tier::kTier1);
  CHECK(r.rigid_body_modes == 1);
  REQUIRE(r.natural_frequencies_hz.size() == 2);
  // 1e-9 (the bound): a 3x3 eigenproblem rounds at ~1e-15; the sampled means were 3.9e-6
  // off.
  CHECK(r.natural_frequencies_hz[0] == Approx(f_low).epsilon(1e-9));
  CHECK(r.natural_frequencies_hz[1] == Approx(f_high).epsilon(1e-9));
}

}  // namespace
}  // namespace gearnvh
