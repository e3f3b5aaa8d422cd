#include "gearnvh/reduction/craig_bampton.h"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/MatOp/SymShiftInvert.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <Eigen/SparseCholesky>
#include <algorithm>

namespace gearnvh {
namespace {

using SpMat = Eigen::SparseMatrix<double>;

// Extracts A(rows, cols) for index maps (-1 = not in the set).
SpMat Block(const SpMat& A, const std::vector<int>& row_map, int rows,
            const std::vector<int>& col_map, int cols) {
  std::vector<Eigen::Triplet<double>> t;
  for (int k = 0; k < A.outerSize(); ++k) {
    for (SpMat::InnerIterator it(A, k); it; ++it) {
      const int r = row_map[it.row()], c = col_map[it.col()];
      if (r >= 0 && c >= 0) t.emplace_back(r, c, it.value());
    }
  }
  SpMat out(rows, cols);
  out.setFromTriplets(t.begin(), t.end());
  return out;
}

}  // namespace

FixedInterfaceModeSet FixedInterfaceModes(const SpMat& K, const SpMat& M,
                                          const std::vector<int>& interior, int modes,
                                          const ReductionOptions& options) {
  FixedInterfaceModeSet out;
  const int n = static_cast<int>(K.rows());
  const int ni = static_cast<int>(interior.size());
  modes = std::clamp(modes, 0, ni);
  out.shapes = Eigen::MatrixXd::Zero(n, modes);
  out.omega2 = Eigen::VectorXd::Zero(modes);
  if (modes == 0) return out;
  std::vector<int> interior_map(n, -1);
  for (int k = 0; k < ni; ++k) interior_map[interior[k]] = k;
  const SpMat Kii = Block(K, interior_map, ni, interior_map, ni);
  const SpMat Mii = Block(M, interior_map, ni, interior_map, ni);
  Eigen::MatrixXd phi;
  Eigen::VectorXd w2;
  const int ncv = std::min(ni, std::max(2 * modes + 1, modes + 20));
  if (ni >= options.dense_eigen_threshold && ncv < ni) {
    using Op = Spectra::SymShiftInvert<double, Eigen::Sparse, Eigen::Sparse>;
    using BOp = Spectra::SparseSymMatProd<double>;
    Op op(Kii, Mii);
    BOp bop(Mii);
    Spectra::SymGEigsShiftSolver<Op, BOp, Spectra::GEigsMode::ShiftInvert> solver(op, bop, modes,
                                                                                  ncv, 0.0);
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-12);
    if (solver.info() != Spectra::CompInfo::Successful) {
      out.status = CraigBamptonStatus::kEigenNotConverged;
      out.message = "Spectra shift-invert eigensolver did not converge";
      return out;
    }
    w2 = solver.eigenvalues();
    phi = solver.eigenvectors();
    out.sparse_eigensolver = true;
  } else {
    const Eigen::MatrixXd kd(Kii), md(Mii);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(kd, md);
    w2 = dense.eigenvalues().head(modes);
    phi = dense.eigenvectors().leftCols(modes);
  }
  // Ascending order.
  std::vector<int> order(modes);
  for (int j = 0; j < modes; ++j) order[j] = j;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return w2[a] < w2[b]; });
  for (int j = 0; j < modes; ++j) {
    out.omega2[j] = w2[order[j]];
    for (int r = 0; r < ni; ++r) out.shapes(interior[r], j) = phi(r, order[j]);
  }
  return out;
}

CraigBamptonBasis CraigBampton(const SpMat& K, const SpMat& M, const std::vector<int>& boundary,
                               int modes, const ReductionOptions& options) {
  CraigBamptonBasis out;
  const int n = static_cast<int>(K.rows());
  const int nb = static_cast<int>(boundary.size());
  std::vector<int> boundary_map(n, -1), interior_map(n, -1), interior;
  for (int k = 0; k < nb; ++k) boundary_map[boundary[k]] = k;
  for (int i = 0; i < n; ++i) {
    if (boundary_map[i] < 0) {
      interior_map[i] = static_cast<int>(interior.size());
      interior.push_back(i);
    }
  }
  const int ni = static_cast<int>(interior.size());
  modes = std::clamp(modes, 0, ni);
  out.T = Eigen::MatrixXd::Zero(n, nb + modes);
  for (int k = 0; k < nb; ++k) out.T(boundary[k], k) = 1.0;
  if (ni == 0) return out;

  const SpMat Kii = Block(K, interior_map, ni, interior_map, ni);
  const SpMat Mii = Block(M, interior_map, ni, interior_map, ni);
  const SpMat Kib = Block(K, interior_map, ni, boundary_map, nb);
  Eigen::SimplicialLDLT<SpMat> ldlt(Kii);
  if (ldlt.info() != Eigen::Success || (ldlt.vectorD().array() <= 0.0).any()) {
    out.status = CraigBamptonStatus::kInteriorSingular;
    out.message =
        "the interior stiffness K_ii is not positive definite (a free interior direction)";
    return out;
  }
  const Eigen::MatrixXd psi = -ldlt.solve(Eigen::MatrixXd(Kib));
  for (int r = 0; r < ni; ++r) out.T.row(interior[r]).head(nb) = psi.row(r);
  if (modes == 0) return out;

  const FixedInterfaceModeSet fixed = FixedInterfaceModes(K, M, interior, modes, options);
  if (fixed.status != CraigBamptonStatus::kSuccess) {
    out.status = fixed.status;
    out.message = fixed.message;
    return out;
  }
  out.sparse_eigensolver = fixed.sparse_eigensolver;
  out.fixed_interface_omega2 = fixed.omega2;
  out.T.rightCols(modes) = fixed.shapes;
  return out;
}

}  // namespace gearnvh
