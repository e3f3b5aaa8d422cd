#include "gearnvh/model/modal_analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
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
  double scale = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (M(i, i) > 0.0) scale = std::max(scale, K(i, i) / M(i, i));
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
  for (Eigen::Index i = n - 1; i >= 0 && static_cast<int>(out.frequencies_hz.size()) < count; --i) {
    const double w2 = mu[i] > 0.0 ? 1.0 / mu[i] - shift : std::numeric_limits<double>::infinity();
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
