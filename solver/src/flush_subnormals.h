// Zeroing subnormal entries of a matrix: high powers of a contracting map decay below the
// smallest normal double, and arithmetic on subnormals is ~100x slower on x86. Zeroing them
// changes a result by less than 2.3e-308 per entry.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <limits>

namespace gearnvh::internal {

template <typename Derived>
void FlushSubnormals(Eigen::MatrixBase<Derived>& x) {
  constexpr double kSmallest = std::numeric_limits<double>::min();
  for (Eigen::Index j = 0; j < x.cols(); ++j) {
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
      if (std::abs(x(i, j)) < kSmallest) x(i, j) = 0.0;
    }
  }
}

}  // namespace gearnvh::internal
