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

FixedInterfaceModeSet LowestFixedInterfaceModes(const SpMat& K, const SpMat& M,
                                                const std::vector<std::vector<int>>& interiors,
                                                int modes, const ReductionOptions& options) {
  const size_t parts = interiors.size();
  int available = 0;
  for (const std::vector<int>& interior : interiors) available += static_cast<int>(interior.size());
  modes = std::clamp(modes, 0, available);
  if (modes == 0) return FixedInterfaceModes(K, M, {}, 0, options);
  std::vector<FixedInterfaceModeSet> sets(parts);
  std::vector<int> asked(parts, 0);
  std::vector<bool> stale(parts, true);
  const int share = parts > 0 ? (modes + static_cast<int>(parts) - 1) / static_cast<int>(parts) : 0;
  for (size_t p = 0; p < parts; ++p) {
    asked[p] = std::min(static_cast<int>(interiors[p].size()), share + kClusterLookahead);
  }
  struct Value {
    double omega2;
    size_t part;
    Eigen::Index column;
  };
  std::vector<Value> merged;
  int cut = 0;
  for (;;) {
    for (size_t p = 0; p < parts; ++p) {
      if (!stale[p]) continue;
      sets[p] = FixedInterfaceModes(K, M, interiors[p], asked[p], options);
      if (sets[p].status != CraigBamptonStatus::kSuccess) return sets[p];
      stale[p] = false;
    }
    merged.clear();
    for (size_t p = 0; p < parts; ++p) {
      for (Eigen::Index j = 0; j < sets[p].omega2.size(); ++j) {
        merged.push_back({sets[p].omega2[j], p, j});
      }
    }
    std::stable_sort(merged.begin(), merged.end(),
                     [](const Value& a, const Value& b) { return a.omega2 < b.omega2; });
    Eigen::VectorXd values(static_cast<Eigen::Index>(merged.size()));
    for (size_t k = 0; k < merged.size(); ++k)
      values[static_cast<Eigen::Index>(k)] = merged[k].omega2;
    cut = ClusterCut(values, modes);
    // A part whose modes may continue below the first value cut off is asked for more.
    bool more = false;
    for (size_t p = 0; p < parts; ++p) {
      const Eigen::Index have = sets[p].omega2.size();
      if (have >= static_cast<Eigen::Index>(interiors[p].size())) continue;
      if (cut < values.size() && have > 0 && sets[p].omega2[have - 1] >= values[cut]) continue;
      asked[p] = std::min(static_cast<int>(interiors[p].size()),
                          2 * static_cast<int>(have) + kClusterLookahead);
      stale[p] = more = true;
    }
    if (!more) break;
  }
  FixedInterfaceModeSet out;
  out.shapes = Eigen::MatrixXd::Zero(K.rows(), cut);
  out.omega2 = Eigen::VectorXd::Zero(cut);
  for (int k = 0; k < cut; ++k) {
    const Value& v = merged[static_cast<size_t>(k)];
    out.omega2[k] = v.omega2;
    out.shapes.col(k) = sets[v.part].shapes.col(v.column);
  }
  for (const FixedInterfaceModeSet& s : sets) out.sparse_eigensolver |= s.sparse_eigensolver;
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
