// An ordered real Schur decomposition A = U T U^T (LAPACK dgees, then dtrexc): T quasi-upper
// triangular with its 1x1 and 2x2 diagonal blocks ordered by eigenvalue modulus, largest first,
// U orthonormal. The first columns of U then span the invariant subspace of the largest
// eigenvalues (to rounding), which an eigenvector basis of a non-normal matrix does not give
// without cond(V) amplification.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace gearnvh {

struct OrderedSchur {
  enum class Info { kSuccess, kFailed };  // kFailed: dgees or dtrexc reported an error
  Info info = Info::kFailed;
  Eigen::MatrixXd U, T;
  std::vector<int> block_start;       // first row/column of each diagonal block
  std::vector<double> block_modulus;  // |lambda| of each block, non-increasing
};

OrderedSchur OrderedRealSchur(const Eigen::MatrixXd& A);

}  // namespace gearnvh
