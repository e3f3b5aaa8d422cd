#include "gearnvh/model/modal_analysis.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace gearnvh {

double AbsoluteQuadraticForm(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& x) {
  double sum = 0.0;
  for (int c = 0; c < K.outerSize(); ++c) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(K, c); it; ++it) {
      sum += std::abs(it.value() * x[it.row()] * x[it.col()]);
    }
  }
  return sum;
}

NaturalModes LowestNaturalModes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, int count,
                                bool with_shapes, const StrainMagnitude& magnitude) {
  NaturalModes out;
  const Eigen::Index n = K.rows();
  if (n == 0) return out;
  // The shift's scale: the largest diagonal K_ii / M_ii over the DOFs that carry mass. A massless
  // DOF (a rigid shaft's lateral DOFs when it has only a torsional inertia) projected onto a basis
  // keeps a rounding-level M_ii (~1e-33 of 1 kg, about eps^2), whose ratio made the shift 1e31 and
  // every mode garbage: masses below 1e-20 of the largest count as none (far below any real one:
  // a 1 mm shaft element's tilt inertia is ~1e-12 of a 100 kg lumped mass).
  const double mass_floor = 1e-20 * M.diagonal().maxCoeff();
  double scale = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (M(i, i) > mass_floor) scale = std::max(scale, K(i, i) / M(i, i));
  }
  const double shift = std::max(1e-10 * scale, 1e-300);
  const Eigen::MatrixXd shifted = K + shift * M;
  // The rigid-body test needs the shapes of the lowest modes.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(M, shifted);
  Eigen::MatrixXd absolute;  // |K|, built only when no magnitude is given
  const StrainMagnitude own = [&](const Eigen::VectorXd& x) {
    if (absolute.size() == 0) absolute = K.cwiseAbs();
    const Eigen::VectorXd a = x.cwiseAbs();
    return a.dot(absolute * a);
  };
  // mu ascending means w^2 descending: walk from the largest mu (the lowest modes); rigid-body
  // modes are the lowest, so the walk ends with the count-th elastic mode.
  const Eigen::VectorXd& mu = solver.eigenvalues();
  std::vector<Eigen::VectorXd> kept;
  // Massless DOFs give mu = 0 up to rounding (~1e-16 of the largest mu, 1 / shift): infinite
  // frequencies, not modes; the walk ends there (an elastic mode's mu is 1 / (w^2 + shift), far
  // above 1e-14 of 1 / shift for any w^2 below 1e4 x the largest K_ii / M_ii).
  const double massless = 1e-14 * mu.maxCoeff();
  for (Eigen::Index i = n - 1; i >= 0 && static_cast<int>(out.frequencies_hz.size()) < count; --i) {
    if (!(mu[i] > massless)) break;
    const double w2 = 1.0 / mu[i] - shift;
    // Eigen normalises x^T B x = 1 with B = K + s M, so x^T M x = mu: rescale to x^T M x = 1.
    const Eigen::VectorXd x = solver.eigenvectors().col(i) / std::sqrt(std::max(mu[i], 1e-300));
    if (IsRigidBodyMode(w2, magnitude ? magnitude(x) : own(x))) {
      ++out.rigid_body_modes;
    } else {
      out.frequencies_hz.push_back(std::sqrt(w2) / (2.0 * std::numbers::pi));
      if (with_shapes) kept.push_back(x);
    }
  }
  if (with_shapes) {
    out.shapes.resize(n, static_cast<Eigen::Index>(kept.size()));
    for (size_t c = 0; c < kept.size(); ++c) out.shapes.col(static_cast<Eigen::Index>(c)) = kept[c];
  }
  return out;
}

}  // namespace gearnvh
