#include "gearnvh/model/shaft_misalignment.h"

#include <stdexcept>

namespace gearnvh {

Eigen::VectorXd StaticDeflection(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f,
                                 const Eigen::MatrixXd& free_rotations) {
  Eigen::SparseMatrix<double> held = K;
  if (free_rotations.cols() > 0) {
    // s: the stiffness scale, so the held directions are as well conditioned as the rest.
    const double s = K.diagonal().cwiseAbs().maxCoeff();
    const Eigen::SparseMatrix<double> p = free_rotations.sparseView();
    held += s * Eigen::SparseMatrix<double>(p * p.transpose());
  }
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(held);
  if (solver.info() != Eigen::Success) {
    throw std::runtime_error(
        "static deflection: the structure with its free rotations held is "
        "not positive definite (an unsupported body?)");
  }
  return solver.solve(f);
}

double TiltMisalignment(const Eigen::VectorXd& v, const Eigen::VectorXd& x, int node_a, int node_b,
                        double face_width) {
  double slope = 0.0;
  for (int node : {node_a, node_b}) {
    const int d = 6 * node;
    slope += v[d] * x[d + 4] - v[d + 1] * x[d + 3];
  }
  return -face_width * slope;
}

}  // namespace gearnvh
