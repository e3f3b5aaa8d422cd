#include "gearnvh/model/modal_analysis.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace gearnvh {

NaturalModes LowestNaturalModes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, int count,
                                bool with_shapes) {
  NaturalModes out;
  const Eigen::Index n = K.rows();
  if (n == 0) return out;
  double scale = 0.0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (M(i, i) > 0.0) scale = std::max(scale, K(i, i) / M(i, i));
  }
  const double shift = std::max(1e-10 * scale, 1e-300);
  const Eigen::MatrixXd shifted = K + shift * M;
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> solver(
      M, shifted, with_shapes ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
  // mu ascending means w^2 descending: walk from the largest mu (the lowest modes).
  const Eigen::VectorXd& mu = solver.eigenvalues();
  std::vector<Eigen::Index> kept;
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    const double w2 = mu[i] > 0.0 ? 1.0 / mu[i] - shift : std::numeric_limits<double>::infinity();
    if (w2 <= 1e-8 * shift) {
      ++out.rigid_body_modes;
    } else if (static_cast<int>(out.frequencies_hz.size()) < count) {
      out.frequencies_hz.push_back(std::sqrt(w2) / (2.0 * std::numbers::pi));
      kept.push_back(i);
    }
  }
  if (with_shapes) {
    out.shapes.resize(n, static_cast<Eigen::Index>(kept.size()));
    for (size_t c = 0; c < kept.size(); ++c) {
      // Eigen normalises x^T B x = 1 with B = K + s M; rescale to x^T M x = 1.
      Eigen::VectorXd x = solver.eigenvectors().col(kept[c]);
      x /= std::sqrt(x.dot(M * x));
      out.shapes.col(static_cast<Eigen::Index>(c)) = x;
    }
  }
  return out;
}

}  // namespace gearnvh
