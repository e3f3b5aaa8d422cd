#include "gearnvh/model/modal_analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

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
  // The rigid-body test needs every shape.
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(M, shifted);
  const Eigen::MatrixXd absolute = K.cwiseAbs();
  const StrainMagnitude own = [&](const Eigen::VectorXd& x) {
    const Eigen::VectorXd a = x.cwiseAbs();
    return a.dot(absolute * a);
  };
  // mu ascending means w^2 descending: walk from the largest mu (the lowest modes).
  const Eigen::VectorXd& mu = solver.eigenvalues();
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    const double w2 = mu[i] > 0.0 ? 1.0 / mu[i] - shift : std::numeric_limits<double>::infinity();
    // Eigen normalises x^T B x = 1 with B = K + s M; rescale to x^T M x = 1.
    Eigen::VectorXd x = solver.eigenvectors().col(i);
    x /= std::sqrt(x.dot(M * x));
    if (IsRigidBodyMode(w2, magnitude ? magnitude(x) : own(x))) {
      ++out.rigid_body_modes;
    } else if (static_cast<int>(out.frequencies_hz.size()) < count) {
      out.frequencies_hz.push_back(std::sqrt(w2) / (2.0 * std::numbers::pi));
      if (with_shapes) {
        out.shapes.conservativeResize(n, out.shapes.cols() + 1);
        out.shapes.col(out.shapes.cols() - 1) = x;
      }
    }
  }
  if (with_shapes && out.shapes.cols() == 0) out.shapes.resize(n, 0);
  return out;
}

}  // namespace gearnvh
