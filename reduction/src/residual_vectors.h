// Modal truncation augmentation (docs/design.md §3): the residual vectors that put static shapes
// into a truncated modal basis. Shared by the pair's and the train's N20 MTA.
//
// MTA adds, per mesh and flank (the load v, its line-of-action vector), two static shapes of the
// structure without meshes, whose bodies turn freely (rigid-body modes Phi_r, M-orthonormal, one
// free rotation per body):
//   held             K x = v with each body's rotation held where the load torques act: the
//                    static compliance and the loaded static state stay exact;
//   inertia relief   K x = (I - M Phi_r Phi_r^T) v, the load balanced by the bodies' own inertia,
//                    as a mesh force is in vibration: the quasi-static response of the truncated
//                    modes (the free-free residual flexibility).
// Their span has at most one direction per elastic shaft beyond the held shapes (the difference is
// the held response to a body's rigid inertia load, which a rigid body carries at its held
// rotation without deflecting); AugmentWithResiduals drops what is spanned.
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

// The loads V (columns) with the inertia of the rigid-body modes `rigid` (M-orthonormal columns)
// balancing them: (I - M Phi_r Phi_r^T) V.
inline Eigen::MatrixXd InertiaRelievedLoads(const Eigen::MatrixXd& V, const Eigen::MatrixXd& M,
                                            const Eigen::MatrixXd& rigid) {
  return V - M * (rigid * (rigid.transpose() * V));
}

}  // namespace gearnvh
