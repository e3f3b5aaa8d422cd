#include "gearnvh/model/component_model.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "model/test_specs.h"

namespace gearnvh {
namespace {

using testing::StandardPair;

// Two shafts on bearings, pinion and wheel mid-span-ish, for the flexible assembly.
GearboxSpec FlexiblePair(double element_length) {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  for (int s = 0; s < 2; ++s) {
    ShaftSpec shaft;
    shaft.material = "steel";
    shaft.segments = {{0.1, 0.035, 0.0}, {0.14, 0.04, 0.01}};
    shaft.gear_at = s == 0 ? 0.1 : 0.13;
    shaft.bearings = {{0.01, 3e8, 1e8, 0.0, 500.0}, {0.23, 3e8, 0.0, 0.0, 500.0}};
    shaft.inertias = {{0.0, 0.02, 0.01}};
    shaft.element_length = element_length;
    (s == 0 ? spec.input_shaft : spec.output_shaft) = shaft;
  }
  return spec;
}

void CheckStructure(const ComponentModel& m) {
  const Eigen::MatrixXd M(m.M), K(m.K), G(m.G), C(m.C);
  const double tol = 1e-12;  // assembly of symmetric element blocks: exact to rounding
  CHECK((M - M.transpose()).norm() <= tol * M.norm());
  CHECK((K - K.transpose()).norm() <= tol * K.norm());
  CHECK((C - C.transpose()).norm() <= tol * (C.norm() + 1.0));
  CHECK((G + G.transpose()).norm() <= tol * (G.norm() + 1.0));
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
  CHECK(eig.eigenvalues().minCoeff() > 0.0);
}

TEST_CASE("rigid-shaft model: structure, one rigid-body rotation, mesh vectors", "[component]") {
  GearboxSpec spec = StandardPair(27, 43);
  const ComponentModel m = BuildComponentModel(spec);
  CHECK(m.dofs == 12);
  CHECK_FALSE(m.flexible);
  CheckStructure(m);
  const ModalSummary modes = FullModelFrequencies(m, 10);
  CHECK(modes.rigid_body_modes == 1);  // free rotation of the pair (no torsional ground)
  CHECK(modes.frequencies_hz.size() == 10);
  // Torsional parts of both gap vectors are the base radii (delta = r_b1 th1 - r_b2 th2 running).
  CHECK(m.v_drive[m.PinionDof(kThz)] == m.geometry.pinion.base);
  CHECK(m.v_drive[m.WheelDof(kThz)] == m.geometry.wheel.base);
  CHECK(m.v_back[m.PinionDof(kThz)] == m.geometry.pinion.base);
  // Unit line-of-action directions on each gear.
  const double n2 = m.v_drive[m.PinionDof(kUx)] * m.v_drive[m.PinionDof(kUx)] +
                    m.v_drive[m.PinionDof(kUy)] * m.v_drive[m.PinionDof(kUy)];
  CHECK(n2 == Approx(1.0).epsilon(1e-15));
  // m_e and c = 2 zeta sqrt(k m_e) as docs/design.md §4.1 defines them.
  const double j1 = m.pinion_body.polar, j2 = m.wheel_body.polar;
  const double rb1 = m.geometry.pinion.base, rb2 = m.geometry.wheel.base;
  CHECK(m.effective_mass == Approx(j1 * j2 / (j1 * rb2 * rb2 + j2 * rb1 * rb1)).epsilon(1e-15));
  CHECK(m.mesh_damping ==
        Approx(2 * 0.05 * std::sqrt(m.mesh_summary.mean * m.effective_mass)).epsilon(1e-15));
}

TEST_CASE("the static load carries no net torque on the rigid-body rotation", "[component]") {
  // docs/design.md §4.1: pinion driven by T r_b1/r_b2, wheel resisted by T: the rigid rotation
  // (th1 = 1/r_b1 on every pinion-shaft node, th_z2 = -1/r_b2 on the wheel shaft) does no work.
  for (const GearboxSpec& spec : {StandardPair(27, 43), FlexiblePair(0.02)}) {
    const ComponentModel m = BuildComponentModel(spec);
    Eigen::VectorXd rigid = Eigen::VectorXd::Zero(m.dofs);
    for (size_t k = 0; k < m.nodes.size(); ++k) {
      rigid[6 * k + kThz] =
          m.nodes[k].shaft == 0 ? 1.0 / m.geometry.pinion.base : -1.0 / m.geometry.wheel.base;
    }
    CHECK(std::abs(m.static_force.dot(rigid)) <= 1e-12 * m.static_force.norm() * rigid.norm());
    CHECK(std::abs(m.v_drive.dot(rigid)) <= 1e-12 * rigid.norm());  // and it opens no gap
    CHECK((Eigen::MatrixXd(m.K) * rigid).norm() <=
          1e-9 * Eigen::MatrixXd(m.K).norm() * rigid.norm());
  }
}

TEST_CASE("flexible shafts: structure, element count, frequencies converge from above",
          "[component]") {
  const ComponentModel coarse = BuildComponentModel(FlexiblePair(0.04));
  const ComponentModel fine = BuildComponentModel(FlexiblePair(0.01));
  const ComponentModel finer = BuildComponentModel(FlexiblePair(0.005));
  CHECK(fine.flexible);
  CheckStructure(fine);
  CHECK(fine.dofs > coarse.dofs);
  const auto fc = FullModelFrequencies(coarse, 6), ff = FullModelFrequencies(fine, 6),
             fx = FullModelFrequencies(finer, 6);
  CHECK(ff.rigid_body_modes == 1);
  // Consistent-mass FE is a Rayleigh–Ritz method: refining the mesh enlarges the trial space, so
  // each frequency decreases monotonically towards the converged value (0.1 % slack for rounding
  // in nearly converged torsion modes).
  for (int i = 0; i < 6; ++i) {
    CHECK(ff.frequencies_hz[i] <= fc.frequencies_hz[i] * (1 + 1e-9));
    CHECK(fx.frequencies_hz[i] <= ff.frequencies_hz[i] * (1 + 1e-9));
    CHECK(fx.frequencies_hz[i] == Approx(ff.frequencies_hz[i]).epsilon(1e-3));
  }
  // Polar inertia on the pinion side: gear + lumped 0.02 + shaft.
  CHECK(fine.pinion_side_inertia > 0.02 + fine.pinion_body.polar);
}

TEST_CASE("friction vector: torsional arms and translation along t = z x n", "[component]") {
  const ComponentModel m = BuildComponentModel(StandardPair(27, 43));
  const Eigen::VectorXd w = m.FrictionVector(Flank::kDrive, 1.0, 0.01, 0.02);
  CHECK(w[m.PinionDof(kThz)] == 0.01);
  CHECK(w[m.WheelDof(kThz)] == 0.02);
  // t is perpendicular to n in the transverse plane.
  const double dot = w[m.PinionDof(kUx)] * m.v_drive[m.PinionDof(kUx)] +
                     w[m.PinionDof(kUy)] * m.v_drive[m.PinionDof(kUy)];
  CHECK(std::abs(dot) < 1e-15);
  CHECK(w[m.WheelDof(kUx)] == -w[m.PinionDof(kUx)]);
}

}  // namespace
}  // namespace gearnvh
