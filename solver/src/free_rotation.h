// Projecting the free rotation out of tangent columns, shared by the pair (SegmentTables) and
// gear trains (TrainTables): both hold n, the M-normalised rotation r and the row r^T M.
#pragma once

#include <Eigen/Dense>

namespace gearnvh {

// V.x <- V.x - r (r^T M V.x) and V.x' <- V.x' - r (r^T M V.x'): position and velocity of the free
// rotation removed M-orthogonally from every column.
template <typename Tables>
void ProjectOutFreeRotation(const Tables& t, Eigen::Ref<Eigen::MatrixXd> V) {
  const int n = t.n;
  for (Eigen::Index c = 0; c < V.cols(); ++c) {
    const double position = t.recenter_row.dot(V.col(c).head(n));
    const double velocity = t.recenter_row.dot(V.col(c).segment(n, n));
    V.col(c).head(n) -= position * t.rigid_rotation;
    V.col(c).segment(n, n) -= velocity * t.rigid_rotation;
  }
}

}  // namespace gearnvh
