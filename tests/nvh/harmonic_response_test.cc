// The harmonic solver against a closed form (one mesh between two bodies) and against an
// independent time integration of the same equations (RK4 to the periodic steady state).
#include "gearnvh/nvh/harmonic_response.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <complex>
#include <numbers>

using gearnvh::HarmonicInput;
using gearnvh::HarmonicModel;
using gearnvh::HarmonicResponse;
using gearnvh::HarmonicSolver;

namespace {

using Complex = std::complex<double>;

// Two rigid bodies J1, J2 joined by one mesh of base radii r1, r2: delta = r1 th1 - r2 th2 obeys
// m_e delta'' + c delta' + k delta = k e, m_e = J1 J2 / (J1 r2^2 + J2 r1^2).
HarmonicModel TwoBodies(double j1, double j2, double r1, double r2, double k, double c) {
  HarmonicModel m;
  m.M = Eigen::Vector2d(j1, j2).asDiagonal();
  m.C = m.G = m.K = Eigen::Matrix2d::Zero();
  m.mesh_vectors = {Eigen::Vector2d(r1, -r2)};
  m.te_vectors = m.mesh_vectors;
  m.mesh_stiffness = {k};
  m.mesh_damping = {c};
  m.body_angles = Eigen::Matrix2d::Identity();
  return m;
}

}  // namespace

TEST_CASE("harmonic response: one mesh between two bodies is the 2-DOF closed form",
          "[nvh][whine]") {
  const double j1 = 2e-3, j2 = 7e-3, r1 = 0.02, r2 = 0.035, k = 3e8, c = 900.0;
  const HarmonicModel model = TwoBodies(j1, j2, r1, r2, k, c);
  HarmonicSolver solver(model);
  solver.SetSpeed(100.0);
  const double me = j1 * j2 / (j1 * r2 * r2 + j2 * r1 * r1);
  HarmonicResponse out;
  // Below, at and above the mesh resonance sqrt(k / m_e).
  for (double w : {0.2, 1.0, 3.0}) {
    const double omega = w * std::sqrt(k / me);
    const Complex e(1.5e-6, -0.4e-6);
    solver.Solve(omega, {{e}, {}}, out);
    const Complex expected = k * e / (k - omega * omega * me + Complex(0.0, omega * c));
    // A 2 x 2 LU: rounding only.
    CHECK(std::abs(out.te[0] - expected) <= 1e-12 * std::abs(expected));
    const Complex force = (k + Complex(0.0, omega * c)) * expected - k * e;
    CHECK(std::abs(out.mesh_force[0] - force) <= 1e-10 * std::abs(force));
    // A torque on body 1 alone: delta responds as to an input r1 T / (J1 k) ... through the same
    // transfer: m_e delta'' + c delta' + k delta = m_e r1 T / J1.
    const Complex torque(2.0, 0.5);
    solver.Solve(omega, {{}, {torque}}, out);
    const Complex from_torque =
        me * r1 * torque / j1 / (k - omega * omega * me + Complex(0.0, omega * c));
    CHECK(std::abs(out.te[0] - from_torque) <= 1e-12 * std::abs(from_torque));
  }
}

TEST_CASE("harmonic response: equals an RK4 integration to the periodic steady state",
          "[nvh][whine]") {
  // Four DOF: stiffness and damping with a gyroscopic part, two meshes, a torque, one bearing.
  HarmonicModel m;
  m.M = Eigen::Vector4d(1.0, 2.0, 1.5, 0.7).asDiagonal();
  Eigen::Matrix4d a;
  a << 2, -1, 0, 0.3, -1, 3, -0.5, 0, 0, -0.5, 2.5, -1, 0.3, 0, -1, 1.8;
  m.K = 400.0 * a;
  m.C = 4.0 * Eigen::Matrix4d::Identity() + 0.002 * m.K;  // every mode decays at >= 1 /s
  m.G = Eigen::Matrix4d::Zero();
  m.G(1, 2) = 0.05;
  m.G(2, 1) = -0.05;
  m.mesh_vectors = {Eigen::Vector4d(1.0, -0.5, 0.0, 0.0), Eigen::Vector4d(0.0, 0.8, -1.2, 0.4)};
  // The second mesh's TE along another vector (as a back-flank-loaded mesh's drive vector).
  m.te_vectors = {m.mesh_vectors[0], Eigen::Vector4d(0.0, 0.8, -1.2, -0.4)};
  m.mesh_stiffness = {900.0, 600.0};
  m.mesh_damping = {1.5, 0.9};
  m.bearing_stiffness = {Eigen::MatrixXd::Zero(3, 4)};
  m.bearing_stiffness[0](0, 0) = 5e3;
  m.bearing_stiffness[0](1, 3) = 2e3;
  m.bearing_damping = {Eigen::MatrixXd::Zero(3, 4)};
  m.bearing_damping[0](0, 0) = 3.0;
  // Body 0's angle (its speed is checked) and body 1's, which the torque acts on.
  m.body_angles = Eigen::Matrix<double, 2, 4>();
  m.body_angles << 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0;
  const double speed = 10.0, omega = 17.0;
  const HarmonicInput input{{Complex(0.3, 0.1), Complex(-0.2, 0.25)}, {0.0, Complex(0.5, -1.0)}};
  HarmonicSolver solver(m);
  solver.SetSpeed(speed);
  HarmonicResponse out;
  solver.Solve(omega, input, out);

  // M q'' + D q' + S q = Re(F e^{i w t}) from rest, RK4, then the Fourier coefficient of each
  // output over the last period (trapezoid: spectrally exact on a smooth periodic signal).
  Eigen::Matrix4d stiffness = m.K, damping = m.C + speed * m.G;
  Eigen::Vector4cd force = input.body_torque[1] * Eigen::Vector4cd(0.0, 0.0, 0.0, 1.0);
  for (size_t i = 0; i < 2; ++i) {
    const Eigen::Vector4d v = m.mesh_vectors[i];
    stiffness += m.mesh_stiffness[i] * v * v.transpose();
    damping += m.mesh_damping[i] * v * v.transpose();
    force += m.mesh_stiffness[i] * input.mesh[i] * v.cast<Complex>();
  }
  const Eigen::Matrix4d minv = m.M.inverse();
  const auto rate = [&](double t, const Eigen::Matrix<double, 8, 1>& y) {
    Eigen::Matrix<double, 8, 1> d;
    const Eigen::Vector4d f = (force * std::exp(Complex(0.0, omega * t))).real();
    d.head<4>() = y.tail<4>();
    d.tail<4>() = minv * (f - damping * y.tail<4>() - stiffness * y.head<4>());
    return d;
  };
  const double period = 2.0 * std::numbers::pi / omega;
  const int per_period = 4000, periods = 120;
  const double h = period / per_period;
  Eigen::Matrix<double, 8, 1> y = Eigen::Matrix<double, 8, 1>::Zero();
  std::vector<Complex> approach(2, 0.0), mesh_force(2, 0.0);
  Complex bearing_x = 0.0, body_speed = 0.0;
  for (int step = 0; step < per_period * periods; ++step) {
    const double t = step * h;
    if (step >= per_period * (periods - 1)) {
      // Sample at the start of the step; weight 2/N of one period (the trapezoid of a periodic
      // function).
      const Complex phase = std::exp(Complex(0.0, -omega * t)) * (2.0 / per_period);
      const Eigen::Vector4d q = y.head<4>(), qd = y.tail<4>();
      for (size_t i = 0; i < 2; ++i) {
        const double delta = m.mesh_vectors[i].dot(q);
        const double e = (input.mesh[i] * std::exp(Complex(0.0, omega * t))).real();
        approach[i] += m.te_vectors[i].dot(q) * phase;
        mesh_force[i] +=
            (m.mesh_stiffness[i] * (delta - e) + m.mesh_damping[i] * m.mesh_vectors[i].dot(qd)) *
            phase;
      }
      bearing_x +=
          (m.bearing_stiffness[0].row(0).dot(q) + m.bearing_damping[0].row(0).dot(qd)) * phase;
      body_speed += m.body_angles.row(0).dot(qd) * phase;
    }
    const Eigen::Matrix<double, 8, 1> k1 = rate(t, y), k2 = rate(t + h / 2, y + h / 2 * k1),
                                      k3 = rate(t + h / 2, y + h / 2 * k2),
                                      k4 = rate(t + h, y + h * k3);
    y += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  // RK4's error at 4000 steps per period (h w = 1.6e-3) is ~(h w)^4 ~ 1e-11 per unit time, and
  // the slowest transient (>= 1 /s) has decayed by e^-44 over 120 periods (44 s): 1e-7 is loose.
  for (size_t i = 0; i < 2; ++i) {
    CHECK(std::abs(out.te[i] - approach[i]) <= 1e-7 * std::abs(approach[i]));
    CHECK(std::abs(out.mesh_force[i] - mesh_force[i]) <= 1e-7 * std::abs(mesh_force[i]));
  }
  CHECK(std::abs(out.bearing_force[0][0] - bearing_x) <= 1e-7 * std::abs(bearing_x));
  CHECK(std::abs(out.body_speed[0] - body_speed) <= 1e-7 * std::abs(body_speed));
}
