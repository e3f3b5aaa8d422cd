// Modal truncation augmentation (docs/design.md §3): the residual vectors that put static shapes
// into a truncated modal basis. Shared by the pair's and the train's N20 MTA.
#pragma once

#include <Eigen/Dense>

namespace gearnvh {

// The M-orthonormal residual vectors of the static shapes X (columns) against the M-orthonormal
// basis P: X - P P^T M X, orthonormalised; a direction the kept modes (or the other shapes)
// already span, at 1e-14 of the largest, is dropped. Returns [P, residuals].
inline Eigen::MatrixXd AugmentWithResiduals(Eigen::MatrixXd P, const Eigen::MatrixXd& M,
                                            const Eigen::MatrixXd& X) {
  const Eigen::MatrixXd R = X - P * (P.transpose() * M * X);
  const Eigen::MatrixXd gram = R.transpose() * M * R;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(0.5 * (gram + gram.transpose()));
  const double largest = eig.eigenvalues().size() > 0 ? eig.eigenvalues().maxCoeff() : 0.0;
  for (Eigen::Index k = 0; k < eig.eigenvalues().size(); ++k) {
    const double lambda = eig.eigenvalues()[k];
    if (!(lambda > 1e-14 * largest)) continue;
    P.conservativeResize(Eigen::NoChange, P.cols() + 1);
    P.rightCols(1) = R * eig.eigenvectors().col(k) / std::sqrt(lambda);
  }
  return P;
}

}  // namespace gearnvh
