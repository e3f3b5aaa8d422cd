#include "gearnvh/model/timoshenko_beam.h"

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

namespace gearnvh {
namespace {

const Material kSteel{206e9, 0.3, 7850.0};

struct Assembled {
  Eigen::MatrixXd K, M, G;
};

// A uniform shaft of n elements along z, all 6 DOF per node.
Assembled UniformBeam(double length, double diameter, int n, bool shear = true) {
  const BeamSection sec = BeamSection::Tube(diameter, 0.0, kSteel.poisson_ratio);
  const BeamElementMatrices e = TimoshenkoBeamElement(sec, kSteel, length / n, shear);
  const int dofs = 6 * (n + 1);
  Assembled a{Eigen::MatrixXd::Zero(dofs, dofs), Eigen::MatrixXd::Zero(dofs, dofs),
              Eigen::MatrixXd::Zero(dofs, dofs)};
  for (int k = 0; k < n; ++k) {
    a.K.block<12, 12>(6 * k, 6 * k) += e.stiffness;
    a.M.block<12, 12>(6 * k, 6 * k) += e.mass;
    a.G.block<12, 12>(6 * k, 6 * k) += e.gyroscopic;
  }
  return a;
}

// Frequencies (Hz, ascending) after keeping only the listed DOFs.
std::vector<double> Frequencies(const Assembled& a, const std::vector<int>& keep) {
  const int n = static_cast<int>(keep.size());
  Eigen::MatrixXd K(n, n), M(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) K(i, j) = a.K(keep[i], keep[j]), M(i, j) = a.M(keep[i], keep[j]);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> s(K, M);
  std::vector<double> f;
  for (int i = 0; i < n; ++i) f.push_back(std::sqrt(std::max(s.eigenvalues()[i], 0.0)) / (2 * std::numbers::pi));
  return f;
}

// DOF indices of one bending plane (x–z: u_x, th_y) over all nodes, minus those in `drop`.
std::vector<int> PlaneDofs(int nodes, std::vector<int> drop, bool xz = true) {
  std::vector<int> keep;
  for (int k = 0; k < nodes; ++k) {
    for (int local : xz ? std::vector<int>{0, 4} : std::vector<int>{1, 3}) {
      const int d = 6 * k + local;
      if (std::find(drop.begin(), drop.end(), d) == drop.end()) keep.push_back(d);
    }
  }
  return keep;
}

TEST_CASE("Euler–Bernoulli cantilever and free-free frequencies match the closed form",
          "[fe][beam]") {
  // Closed form: w = (beta L)^2 sqrt(E I / (rho A L^4)); cantilever beta L = 1.8751041,
  // free-free 4.7300408. 40 cubic elements converge to well below 0.5 % (the bound);
  // slender beam and shear switched off to compare with Euler–Bernoulli theory.
  const double L = 1.0, d = 0.02;
  const int n = 40;
  const Assembled a = UniformBeam(L, d, n, /*shear=*/false);
  const double A = std::numbers::pi * d * d / 4, I = std::numbers::pi * std::pow(d, 4) / 64;
  const double base = std::sqrt(206e9 * I / (7850.0 * A * std::pow(L, 4))) / (2 * std::numbers::pi);
  for (bool xz : {true, false}) {
    const auto cant = Frequencies(a, PlaneDofs(n + 1, {0, 1, 3, 4}, xz));  // clamp node 0
    CHECK(cant[0] == Approx(1.8751041 * 1.8751041 * base).epsilon(0.005));
    CHECK(cant[1] == Approx(4.6940911 * 4.6940911 * base).epsilon(0.005));
    const auto free = Frequencies(a, PlaneDofs(n + 1, {}, xz));
    CHECK(free[0] < 1e-3 * base);  // two rigid-body modes per plane
    CHECK(free[1] < 1e-3 * base);
    CHECK(free[2] == Approx(4.7300408 * 4.7300408 * base).epsilon(0.005));
  }
}

TEST_CASE("Timoshenko shear and rotary inertia lower a stubby beam's frequency as theory says",
          "[fe][beam]") {
  // Simply supported Timoshenko beam, mode m, k = m pi / L: w^2 solves
  //   (rho I rho / (kappa G)) w^4 - (rho A + k^2 (rho I + E I rho / (kappa G))) w^2 + E I k^4 = 0
  // (lower root). L/d = 3: shear lowers the first frequency by tens of percent against EB theory.
  const double L = 0.06, d = 0.02, E = 206e9, rho = 7850, nu = 0.3, G = E / (2 * (1 + nu));
  const BeamSection sec = BeamSection::Tube(d, 0.0, nu);
  const double A = sec.area, I = sec.second_moment, kappa = sec.shear_coefficient;
  const int n = 60;
  const Assembled a = UniformBeam(L, d, n, true);
  const auto fe = Frequencies(a, PlaneDofs(n + 1, {0, 6 * n + 0}, true));  // u_x = 0 at both ends
  for (int m = 1; m <= 2; ++m) {
    const double k = m * std::numbers::pi / L;
    const double qa = rho * I * rho / (kappa * G);
    const double qb = rho * A + k * k * (rho * I + E * I * rho / (kappa * G));
    const double qc = E * I * k * k * k * k;
    const double w2 = (qb - std::sqrt(qb * qb - 4 * qa * qc)) / (2 * qa);
    const double exact = std::sqrt(w2) / (2 * std::numbers::pi);
    const double euler = k * k * std::sqrt(E * I / (rho * A)) / (2 * std::numbers::pi);
    INFO("mode " << m << " Timoshenko " << exact << " Hz, Euler-Bernoulli " << euler << " Hz");
    CHECK(exact < 0.9 * euler);                        // the effect is large at L/d = 3
    CHECK(fe[m - 1] == Approx(exact).epsilon(0.005));  // and the element reproduces it
  }
}

TEST_CASE("torsional and axial frequencies match the closed forms", "[fe][beam]") {
  // Free-free rod: f_m = m / (2 L) sqrt(G / rho) (torsion), m / (2 L) sqrt(E / rho) (axial).
  const double L = 0.5, d = 0.03;
  const int n = 40;
  const Assembled a = UniformBeam(L, d, n);
  std::vector<int> torsion, axial;
  for (int k = 0; k <= n; ++k) torsion.push_back(6 * k + 5), axial.push_back(6 * k + 2);
  const auto ft = Frequencies(a, torsion), fa = Frequencies(a, axial);
  const double G = 206e9 / 2.6;
  CHECK(ft[0] < 1e-6 * ft[1]);
  CHECK(fa[0] < 1e-6 * fa[1]);
  for (int m = 1; m <= 3; ++m) {
    // Linear elements with consistent mass converge as (m / n)^2: 0.5 % covers m <= 3 at n = 40.
    CHECK(ft[m] == Approx(m / (2 * L) * std::sqrt(G / 7850.0)).epsilon(0.005));
    CHECK(fa[m] == Approx(m / (2 * L) * std::sqrt(206e9 / 7850.0)).epsilon(0.005));
  }
}

TEST_CASE(
    "element matrices: M symmetric positive definite, K symmetric PSD with 6 rigid modes, G skew",
    "[fe][beam]") {
  const Assembled a = UniformBeam(0.3, 0.04, 10);
  const double tol = 1e-12;
  CHECK((a.M - a.M.transpose()).norm() <= tol * a.M.norm());
  CHECK((a.K - a.K.transpose()).norm() <= tol * a.K.norm());
  CHECK((a.G + a.G.transpose()).norm() <= tol * a.G.norm());
  CHECK(a.G.norm() > 0.0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> m(a.M);
  CHECK(m.eigenvalues().minCoeff() > 0.0);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> k(a.K, a.M);
  const Eigen::VectorXd w2 = k.eigenvalues();
  int zero = 0;
  for (int i = 0; i < w2.size(); ++i) {
    CHECK(w2[i] > -1e-9 * w2.maxCoeff());
    zero += std::abs(w2[i]) < 1e-9 * w2.maxCoeff() ? 1 : 0;
  }
  CHECK(zero == 6);  // 3 translations + 3 rotations of a free body
}

TEST_CASE("Cowper shear coefficient of a solid round section", "[fe][beam]") {
  // kappa = 6 (1 + nu) / (7 + 6 nu): 0.8864 for nu = 0.3 (Cowper 1966, Table 1).
  CHECK(BeamSection::Tube(0.02, 0.0, 0.3).shear_coefficient ==
        Approx(6 * 1.3 / 8.8).epsilon(1e-14));
}

}  // namespace
}  // namespace gearnvh
