// Helical pairs (docs/gear-trains.md): transverse geometry, contact ratios, slice-method stiffness.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/mesh_stiffness.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

using testing::kDeg;

GearboxSpec HelicalPair(double beta, double face = 30e-3) {
  GearboxSpec spec = testing::StandardPair(20, 40, 3e-3, face);
  for (GearSpec* g : {&spec.pinion, &spec.wheel}) g->helix_angle = beta;
  spec.pinion.hand = Hand::kRight;
  spec.wheel.hand = Hand::kLeft;
  spec.pinion.bore_diameter = 30e-3;
  spec.wheel.bore_diameter = 60e-3;
  return spec;
}

TEST_CASE("helical geometry: transverse section and contact ratios by the closed forms",
          "[mesh][helical]") {
  const double beta = 20 * kDeg, an = 20 * kDeg, mn = 3e-3, b = 30e-3;
  const GearboxSpec spec = HelicalPair(beta, b);
  const PairGeometry g = ComputePairGeometry(spec);
  // Independent closed forms (ISO 21771): m_t = m_n / cos b, tan a_t = tan a_n / cos b,
  // r = m_t z / 2, r_b = r cos a_t, r_a = r + m_n, eps_a from the transverse path of contact,
  // eps_b = b sin(beta) / (pi m_n), sin(beta_b) = sin(beta) cos(a_n).
  const double mt = mn / std::cos(beta), at = std::atan(std::tan(an) / std::cos(beta));
  const double r1 = mt * 10, r2 = mt * 20, rb1 = r1 * std::cos(at), rb2 = r2 * std::cos(at);
  const double ra1 = r1 + mn, ra2 = r2 + mn, a = r1 + r2;
  const double pbt = std::numbers::pi * mt * std::cos(at);
  const double eps_a =
      (std::sqrt(ra1 * ra1 - rb1 * rb1) + std::sqrt(ra2 * ra2 - rb2 * rb2) - a * std::sin(at)) /
      pbt;
  const double eps_b = b * std::sin(beta) / (std::numbers::pi * mn);
  // Rounding of a handful of trigonometric operations: 1e-13.
  CHECK(g.pinion.base == Approx(rb1).epsilon(1e-13));
  CHECK(g.wheel.tip == Approx(ra2).epsilon(1e-13));
  CHECK(g.center_distance == Approx(a).epsilon(1e-13));
  CHECK(g.working_pressure_angle == Approx(at).epsilon(1e-12));
  CHECK(g.base_pitch == Approx(pbt).epsilon(1e-13));
  CHECK(g.contact_ratio == Approx(eps_a).epsilon(1e-12));
  CHECK(g.overlap_ratio == Approx(eps_b).epsilon(1e-13));
  CHECK(g.total_contact_ratio == Approx(eps_a + eps_b).epsilon(1e-12));
  CHECK(std::sin(g.base_helix_angle) == Approx(std::sin(beta) * std::cos(an)).epsilon(1e-13));
}

TEST_CASE("the slice method tends to the spur pair as the helix angle vanishes",
          "[mesh][helical]") {
  GearboxSpec spur = HelicalPair(0.0);
  spur.operating.torque = 50.0;
  GearboxSpec nearly = HelicalPair(1e-7);
  nearly.operating.torque = 50.0;
  const PairGeometry gs = ComputePairGeometry(spur), gh = ComputePairGeometry(nearly);
  const MeshStiffnessSummary s = testing::MeshSummaryOf(spur);
  const MeshStiffnessSummary h = testing::MeshSummaryOf(nearly);
  // beta = 1e-7 moves the slices by eps_beta = 3e-7 of a cycle and the transverse module by
  // 5e-15; the spline table interpolates the pair stiffness to ~1e-12. Agreement to 1e-6 is the
  // staircase of slices straddling the contact transitions (3e-7 of a cycle).
  CHECK(h.mean == Approx(s.mean).epsilon(1e-6));
  CHECK(h.max == Approx(s.max).epsilon(1e-6));
  CHECK(h.lste_peak_to_peak == Approx(s.lste_peak_to_peak).epsilon(1e-4));
}

TEST_CASE("an overlap ratio of one smooths the mesh stiffness", "[mesh][helical]") {
  // With eps_beta = 1 the total length of the contact lines is nearly constant over the cycle:
  // the stiffness ripple that is ~40 % for the spur pair drops to a few per cent.
  const double beta = 15 * kDeg;
  const double face = std::numbers::pi * 3e-3 / std::sin(beta);  // eps_beta = 1
  GearboxSpec helical = HelicalPair(beta, face);
  GearboxSpec spur = HelicalPair(0.0, face);
  for (GearboxSpec* s : {&helical, &spur}) s->operating.torque = 50.0;
  const PairGeometry gh = ComputePairGeometry(helical), gs = ComputePairGeometry(spur);
  REQUIRE(gh.overlap_ratio == Approx(1.0).epsilon(1e-12));
  const MeshStiffnessSummary h = testing::MeshSummaryOf(helical);
  const MeshStiffnessSummary s = testing::MeshSummaryOf(spur);
  const double helical_ripple = (h.max - h.min) / h.mean, spur_ripple = (s.max - s.min) / s.mean;
  INFO("ripple helical " << helical_ripple << ", spur " << spur_ripple);
  CHECK(spur_ripple > 0.3);
  CHECK(helical_ripple < 0.1);
}

TEST_CASE("helical mesh stiffness lies within the spread of methods around ISO 6336-1 c_gamma_beta",
          "[mesh][helical][iso]") {
  // ISO 6336-1 method B for solid helical gears: q' with the virtual tooth numbers
  // z_n = z / cos^3(beta) (x = 0), c'_th = 1/q', c' = 0.8 c'_th cos(beta) (C_M = 0.8,
  // C_R = C_B = 1), c_gamma_alpha = c' (0.75 eps_alpha + 0.25), c_gamma_beta = 0.85 c_gamma_alpha,
  // per unit face width along the normal to the flanks. The slice stiffness relates the
  // transverse force and approach: along the normal k_n = k_t / cos^2(beta_b).
  for (double deg : {10.0, 20.0, 30.0}) {
    const double beta = deg * kDeg, face = 30e-3;
    GearboxSpec spec = HelicalPair(beta, face);
    spec.operating.torque = 100.0 * face * 1e3 * 0.5 * 0.06 / std::cos(beta);  // ~100 N/mm
    const PairGeometry g = ComputePairGeometry(spec);
    const MeshStiffnessSummary s = testing::MeshSummaryOf(spec);
    const double zn1 = 20 / std::pow(std::cos(beta), 3), zn2 = 40 / std::pow(std::cos(beta), 3);
    const double q = 0.04723 + 0.15551 / zn1 + 0.25791 / zn2;
    const double c_single = 0.8 / q * std::cos(beta);
    const double c_gamma = 0.85 * c_single * (0.75 * g.contact_ratio + 0.25);  // N/(mm um)
    const double iso = c_gamma * face * 1e3 * 1e6;                             // N/m
    const double normal = s.mean / std::pow(std::cos(g.base_helix_angle), 2);
    INFO(deg << " deg: mean (normal) " << normal << " N/m vs ISO c_gamma_beta b " << iso << " ("
             << 100 * (normal / iso - 1) << " %)");
    CHECK(std::abs(normal / iso - 1.0) < 0.35);
  }
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("the helical mesh vector carries the axial force T tan(beta) / r and its tilting moment",
          "[mesh][helical]") {
  const double beta = 20 * kDeg, torque = 100.0;
  GearboxSpec spec = HelicalPair(beta);
  spec.operating.torque = torque;
  const ComponentModel model = BuildComponentModel(spec);
  // Static equilibrium of the rigid-shaft pair in drive contact at the mean stiffness (the free
  // rotation is unloaded: the minimum-norm solution of the singular system is the static one).
  const Eigen::MatrixXd k = Eigen::MatrixXd(model.K) +
                            model.mesh_summary.mean * model.v_drive * model.v_drive.transpose();
  const Eigen::VectorXd q =
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(k).solve(model.static_force);
  REQUIRE((k * q - model.static_force).norm() < 1e-9 * model.static_force.norm());
  const ComponentModelOptions options;
  const double axial_pinion = options.rigid_axial_stiffness * q[model.PinionDof(kUz)];
  const double axial_wheel = options.rigid_axial_stiffness * q[model.WheelDof(kUz)];
  // ISO 21771: F_a = F_t tan(beta) with F_t = T / r at the pitch circle (transverse), the same as
  // the base-circle force T / r_b times tan(beta_b) since tan(beta_b) = tan(beta) cos(a_t).
  const double r_wheel = 0.5 * spec.wheel.module / std::cos(beta) * spec.wheel.teeth;
  const double expected = torque / r_wheel * std::tan(beta);
  // A 12-DOF solve at condition ~1e8 (bearing vs mesh stiffness): 1e-7 relative.
  CHECK(std::abs(axial_pinion) == Approx(expected).epsilon(1e-7));
  CHECK(axial_wheel == Approx(-axial_pinion).epsilon(1e-7));
  // The axial force acts at the contact point, r_b1 from the pinion's axis: a tilting moment
  // F_a r_b1 reacted by the supports' tilt stiffness.
  const double tilt =
      options.rigid_tilt_stiffness * std::hypot(q[model.PinionDof(kThx)], q[model.PinionDof(kThy)]);
  CHECK(tilt == Approx(expected * model.geometry.pinion.base).epsilon(1e-7));
  // A spur pair has none.
  GearboxSpec spur = HelicalPair(0.0);
  spur.operating.torque = torque;
  const ComponentModel spur_model = BuildComponentModel(spur);
  CHECK(spur_model.v_drive[spur_model.PinionDof(kUz)] == 0.0);
}

}  // namespace
}  // namespace gearnvh
