#include "gearnvh/model/modal_analysis.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

TEST_CASE("rigid-body modes are found whatever the stiffest part of the model", "[modal][rigid]") {
  // Block-diagonal pencil with closed-form modes: two disks on a torsional spring (one free
  // rotation + sqrt(k (1/J1 + 1/J2))), a 60 Hz lateral oscillator, and a bearing-like DOF whose
  // stiffness sweeps up to 1e17 N/m. A relative zero test (w^2 <= 1e-9 w_max^2) calls the 60 Hz
  // mode rigid once w_max^2 > 1.4e14; the criterion on the mode's own strain magnitude must not.
  const double j1 = 0.01, j2 = 0.03, kt = 2e4;
  const double m_lat = 2.0, k_lat = m_lat * std::pow(kTwoPi * 60.0, 2);
  for (double k_stiff : {1e8, 1e13, 1e15, 1e17}) {
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(4, 4), M = Eigen::MatrixXd::Zero(4, 4);
    K.topLeftCorner(2, 2) << kt, -kt, -kt, kt;
    M(0, 0) = j1;
    M(1, 1) = j2;
    K(2, 2) = k_lat;
    M(2, 2) = m_lat;
    K(3, 3) = k_stiff;
    M(3, 3) = 0.05;
    const NaturalModes modes = LowestNaturalModes(K, M, 3, true);
    INFO("bearing stiffness " << k_stiff);
    CHECK(modes.rigid_body_modes == 1);
    REQUIRE(modes.frequencies_hz.size() == 3);
    // Shift-invert accuracy near w^2: eps s / w^2 with s = 1e-10 w_max^2 (<= 1e-13 here); the
    // bound 1e-10 leaves room for the eigensolver's own rounding.
    CHECK(modes.frequencies_hz[0] == Approx(60.0).epsilon(1e-10));
    CHECK(modes.frequencies_hz[1] ==
          Approx(std::sqrt(kt * (1 / j1 + 1 / j2)) / kTwoPi).epsilon(1e-10));
    CHECK(modes.frequencies_hz[2] == Approx(std::sqrt(k_stiff / 0.05) / kTwoPi).epsilon(1e-8));
    // Shapes are M-normalised.
    for (int c = 0; c < 3; ++c) {
      CHECK(modes.shapes.col(c).dot(M * modes.shapes.col(c)) == Approx(1.0).epsilon(1e-12));
    }
  }
}

TEST_CASE("massless DOFs held by springs have no mode and do not set the shift", "[modal][rigid]") {
  // A mass m on a massless DOF between springs k1 and k2 (to ground): one mode at
  // sqrt(k1 k2 / ((k1 + k2) m)). Two disks on a torsional spring: a free rotation and
  // sqrt(kt (1/J1 + 1/J2)). A support DOF of 5e8 N/m whose mass is rounding (1e-33 kg, as a
  // massless DOF projected onto a basis keeps): it must neither give a mode nor set the shift.
  const double m = 2.0, k1 = 1e6, k2 = 3e6, j1 = 0.01, j2 = 0.03, kt = 2e4;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(5, 5), M = Eigen::MatrixXd::Zero(5, 5);
  K.topLeftCorner(2, 2) << k1, -k1, -k1, k1 + k2;
  M(0, 0) = m;
  K(2, 2) = 5e8;
  M(2, 2) = 1e-33;
  K.bottomRightCorner(2, 2) << kt, -kt, -kt, kt;
  M(3, 3) = j1;
  M(4, 4) = j2;
  const NaturalModes modes = LowestNaturalModes(K, M, 5, true);
  CHECK(modes.rigid_body_modes == 1);
  REQUIRE(modes.frequencies_hz.size() == 2);  // no infinite-frequency "modes"
  // Shift-invert accuracy as above (1e-10).
  const double series = std::sqrt(k1 * k2 / ((k1 + k2) * m)) / kTwoPi;
  const double disks = std::sqrt(kt * (1 / j1 + 1 / j2)) / kTwoPi;
  CHECK(modes.frequencies_hz[0] == Approx(std::min(series, disks)).epsilon(1e-10));
  CHECK(modes.frequencies_hz[1] == Approx(std::max(series, disks)).epsilon(1e-10));
}

TEST_CASE("a gear pair on very stiff supports keeps one rigid-body mode", "[modal][rigid]") {
  const GearboxSpec spec = testing::StandardPair(27, 43);
  for (double k : {5e8, 1e13, 1e15}) {
    ComponentModelOptions options;
    options.rigid_radial_stiffness = k;
    options.rigid_axial_stiffness = k;
    const ComponentModel model = BuildComponentModel(spec, options);
    const ModalSummary modes = FullModelFrequencies(model, 12);
    INFO("support stiffness " << k);
    CHECK(modes.rigid_body_modes == 1);  // the pair's free rotation, nothing else
    CHECK(modes.frequencies_hz.size() == 11);
  }
}

}  // namespace
}  // namespace gearnvh
