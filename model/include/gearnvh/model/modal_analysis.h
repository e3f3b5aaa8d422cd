// Undamped natural frequencies of K phi = w^2 M phi, with one rigid-body criterion for every model
// (the full FE model, every modal tier; docs/design.md §3, "Rigid-body modes").
//
// The pencil is solved in shift-invert form M phi = mu (K + s M) phi, w^2 = 1/mu - s, with
// s = 1e-10 max_i K_ii / M_ii: the computed w^2 of the lowest modes carry an absolute error ~eps s,
// so a slow elastic mode keeps its digits however stiff the stiffest part of the model is.
//
// Rigid-body test: a mode is rigid-body when its strain energy w^2 (phi M-normalised) is below
// kRigidBodyCancellation of the magnitude of the terms it is summed from, |phi|^T |K| |phi|. A true
// zero is the cancellation of springs moving rigidly and comes out at ~n eps of that magnitude
// (the rounding of K, and of a reduction's condensation, in the springs the mode moves), whatever
// the model's largest eigenvalue; 1e-10 is three decades above that and leaves such a frequency
// fewer than three significant digits. Measuring against the magnitude the mode itself strains,
// not the largest eigenvalue, keeps a 60 Hz mode elastic beside a 1e17 N/m bearing, and gives a
// reduced tier the verdict of the full model when the magnitude is taken there (StrainMagnitude).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <functional>
#include <vector>

namespace gearnvh {

constexpr double kRigidBodyCancellation = 1e-10;

// |x|^T |K| |x| of a mode shape x (M-normalised, in the pencil's coordinates): the magnitude of
// the terms of its strain energy x^T K x.
using StrainMagnitude = std::function<double(const Eigen::VectorXd& shape)>;

// |x|^T |K| |x| for a sparse K.
double AbsoluteQuadraticForm(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& x);

// The rigid-body test above: w2 is the mode's eigenvalue, magnitude its StrainMagnitude.
inline bool IsRigidBodyMode(double w2, double magnitude) {
  return w2 <= kRigidBodyCancellation * magnitude;
}

struct NaturalModes {
  std::vector<double> frequencies_hz;  // ascending, rigid-body modes excluded
  Eigen::MatrixXd shapes;              // M-normalised shapes of those modes (columns), if asked
  int rigid_body_modes = 0;
};

// The `count` lowest elastic modes of the symmetric pencil (K, M), M and K positive
// semidefinite with K + s M definite for s > 0 (a massless DOF is held by a stiffness: it has no
// mode, its infinite frequency is left out). Shapes are returned when `with_shapes`. `magnitude`
// defaults to |x|^T |K| |x| of this K; a reduced model passes the full model's (shapes recovered).
NaturalModes LowestNaturalModes(const Eigen::MatrixXd& K, const Eigen::MatrixXd& M, int count,
                                bool with_shapes = false, const StrainMagnitude& magnitude = {});

}  // namespace gearnvh
