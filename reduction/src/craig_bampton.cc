#include "gearnvh/reduction/craig_bampton.h"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/MatOp/SymShiftInvert.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <Eigen/SparseCholesky>
#include <algorithm>

#include "mode_cut.h"

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

// The lowest `count` eigenpairs of K_ii phi = w^2 M_ii phi, ascending (false: Spectra did not
// converge).
bool LowestInteriorModes(const SpMat& Kii, const SpMat& Mii, int count,
                         const ReductionOptions& options, Eigen::VectorXd& w2, Eigen::MatrixXd& phi,
                         bool& sparse) {
  const int ni = static_cast<int>(Kii.rows());
  const int ncv = std::min(ni, std::max(2 * count + 1, count + 20));
  sparse = ni >= options.dense_eigen_threshold && ncv < ni;
  Eigen::VectorXd values;
  Eigen::MatrixXd vectors;
  if (sparse) {
    using Op = Spectra::SymShiftInvert<double, Eigen::Sparse, Eigen::Sparse>;
    using BOp = Spectra::SparseSymMatProd<double>;
    Op op(Kii, Mii);
    BOp bop(Mii);
    Spectra::SymGEigsShiftSolver<Op, BOp, Spectra::GEigsMode::ShiftInvert> solver(op, bop, count,
                                                                                  ncv, 0.0);
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-12);
    if (solver.info() != Spectra::CompInfo::Successful) return false;
    values = solver.eigenvalues();
    vectors = solver.eigenvectors();
  } else {
    const Eigen::MatrixXd kd(Kii), md(Mii);
    Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> dense(kd, md);
    values = dense.eigenvalues().head(count);
    vectors = dense.eigenvectors().leftCols(count);
  }
  std::vector<int> order(static_cast<size_t>(count));
  for (int j = 0; j < count; ++j) order[static_cast<size_t>(j)] = j;
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  w2.resize(count);
  phi.resize(ni, count);
  for (int j = 0; j < count; ++j) {
    w2[j] = values[order[static_cast<size_t>(j)]];
    phi.col(j) = vectors.col(order[static_cast<size_t>(j)]);
  }
  return true;
}

// Modes computed past the requested count to see whether the cut ends a cluster.
constexpr int kClusterLookahead = 4;

}  // namespace

FixedInterfaceModeSet FixedInterfaceModes(const SpMat& K, const SpMat& M,
                                          const std::vector<int>& interior, int modes,
                                          const ReductionOptions& options) {
  FixedInterfaceModeSet out;
  const int n = static_cast<int>(K.rows());
  const int ni = static_cast<int>(interior.size());
  modes = std::clamp(modes, 0, ni);
  if (modes == 0) {
    out.shapes = Eigen::MatrixXd::Zero(n, 0);
    out.omega2 = Eigen::VectorXd::Zero(0);
    return out;
  }
  std::vector<int> interior_map(n, -1);
  for (int k = 0; k < ni; ++k) interior_map[interior[k]] = k;
  const SpMat Kii = Block(K, interior_map, ni, interior_map, ni);
  const SpMat Mii = Block(M, interior_map, ni, interior_map, ni);
  Eigen::MatrixXd phi;
  Eigen::VectorXd w2;
  int cut = modes;
  for (int computed = std::min(ni, modes + kClusterLookahead);;
       computed = std::min(ni, 2 * computed)) {
    if (!LowestInteriorModes(Kii, Mii, computed, options, w2, phi, out.sparse_eigensolver)) {
      out.status = CraigBamptonStatus::kEigenNotConverged;
      out.message = "Spectra shift-invert eigensolver did not converge";
      return out;
    }
    cut = ClusterCut(w2, modes);
    if (cut < computed || computed == ni) break;  // the cluster ends inside what is computed
  }
  out.omega2 = w2.head(cut);
  out.shapes = Eigen::MatrixXd::Zero(n, cut);
  for (int r = 0; r < ni; ++r) out.shapes.row(interior[r]) = phi.row(r).head(cut);
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
  out.T = Eigen::MatrixXd::Zero(n, nb);
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
  out.T.conservativeResize(Eigen::NoChange, nb + fixed.shapes.cols());  // a cluster may add modes
  out.T.rightCols(fixed.shapes.cols()) = fixed.shapes;
  return out;
}

}  // namespace gearnvh
