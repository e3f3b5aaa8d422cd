// Where a modal basis may be cut: never inside a cluster of equal eigenvalues. A solver returns
// the members of a degenerate cluster (an axisymmetric shaft's x and y bending) in an arbitrary
// rotation, so a cut inside one keeps an arbitrary direction and the results depend on rounding.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace gearnvh {

// Eigenvalues (omega^2) closer than this, relative to the larger, are one cluster. Axisymmetric
// pairs agree to rounding (~1e-13); at 1e-6 a split member's shape is still well defined (its
// error is about the solver's residual over the gap).
constexpr double kModeClusterTolerance = 1e-6;

// The smallest count >= `count` (clamped to [0, size]) that ends a cluster of the ascending
// eigenvalues `omega2`.
inline int ClusterCut(const Eigen::VectorXd& omega2, int count) {
  const int n = static_cast<int>(omega2.size());
  count = std::clamp(count, 0, n);
  while (count > 0 && count < n &&
         omega2[count] - omega2[count - 1] <=
             kModeClusterTolerance *
                 std::max(std::abs(omega2[count]), std::abs(omega2[count - 1]))) {
    ++count;
  }
  return count;
}

}  // namespace gearnvh
