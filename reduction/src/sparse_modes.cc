#include "gearnvh/reduction/sparse_modes.h"

#include <Spectra/MatOp/SparseSymMatProd.h>
#include <Spectra/MatOp/SymShiftInvert.h>
#include <Spectra/SymGEigsShiftSolver.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace gearnvh {

NaturalModes LowestSparseNaturalModes(const Eigen::SparseMatrix<double>& K,
                                      const Eigen::SparseMatrix<double>& M, int count,
                                      int rigid_body_modes,
                                      const StrainMagnitude& magnitude) {
  double scale = 0.0;
  for (int i = 0; i < K.rows(); ++i) {
    if (M.coeff(i, i) > 0.0) scale = std::max(scale, K.coeff(i, i) / M.coeff(i, i));
  }
  const double shift = -1e-10 * scale;
  using Op = Spectra::SymShiftInvert<double, Eigen::Sparse, Eigen::Sparse>;
  Op op(K, M);
  Spectra::SparseSymMatProd<double> bop(M);
  const int n = static_cast<int>(K.rows());
  const int wanted = std::min(count + rigid_body_modes, n - 1);
  const int ncv = std::min(n, std::max(2 * wanted + 1, wanted + 20));
  Spectra::SymGEigsShiftSolver<Op, Spectra::SparseSymMatProd<double>,
                               Spectra::GEigsMode::ShiftInvert>
      solver(op, bop, wanted, ncv, shift);
  solver.init();
  solver.compute(Spectra::SortRule::LargestMagn, 1000, 1e-10);
  NaturalModes out;
  if (solver.info() != Spectra::CompInfo::Successful) return out;
  const Eigen::VectorXd w2 = solver.eigenvalues();
  const Eigen::MatrixXd phi = solver.eigenvectors();
  std::vector<int> order(static_cast<size_t>(w2.size()));
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return w2[a] < w2[b]; });
  std::vector<Eigen::VectorXd> kept;
  for (int i : order) {
    Eigen::VectorXd x = phi.col(i);
    x /= std::sqrt(x.dot(M * x));
    if (IsRigidBodyMode(w2[i], magnitude ? magnitude(x) : AbsoluteQuadraticForm(K, x))) {
      ++out.rigid_body_modes;
    } else {
      out.frequencies_hz.push_back(std::sqrt(w2[i]) / (2.0 * std::numbers::pi));
      kept.push_back(std::move(x));
    }
  }
  out.shapes.resize(n, static_cast<Eigen::Index>(kept.size()));
  for (size_t c = 0; c < kept.size(); ++c) out.shapes.col(static_cast<Eigen::Index>(c)) = kept[c];
  return out;
}

}  // namespace gearnvh
