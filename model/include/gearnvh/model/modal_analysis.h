// Undamped natural frequencies of K phi = w^2 M phi with a rigid-body criterion that does not
// depend on how stiff the stiffest part of the model is.
//
// A dense solver computes eigenvalues w^2 to an absolute accuracy of ~eps * w_max^2, so a relative
// zero test (w^2 <= 1e-9 w_max^2) calls a 60 Hz bending mode "rigid" once a bearing is stiff
// enough (1e13 N/m). Instead the pencil is solved in shift-invert form
//   M phi = mu (K + s M) phi,   w^2 = 1/mu - s,
// where the computed mu carry an absolute error ~eps / s, so w^2 near zero is accurate to ~eps s.
// The shift s = 1e-10 max_i K_ii / M_ii (the largest eigenvalue is within a factor n of that
// estimate) keeps K + s M factorisable (condition <= ~1e10 n). A mode is rigid-body when
// w^2 <= 1e-8 s: eight decades above the rounding of a true zero, and for any practical model
// below 1e-3 Hz (w_max = 2 pi 1 MHz gives the threshold 2e-4 rad/s).
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace gearnvh {

struct NaturalModes {
  std::vector<double> frequencies_hz;  // ascending, rigid-body modes excluded
  Eigen::MatrixXd shapes;              // M-normalised shapes of those modes (columns), if asked
  int rigid_body_modes = 0;
};

// The `count` lowest elastic modes of the symmetric pencil (K, M), M positive definite and K
// positive semidefinite. Shapes are returned when `with_shapes`.
NaturalModes LowestNaturalModes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, int count,
                                bool with_shapes = false);

}  // namespace gearnvh
