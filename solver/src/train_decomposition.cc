#include "train_decomposition.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gearnvh {
namespace {

// Coordinate j < n is free: its acceleration row and its position and velocity columns are zero
// on the 2n coordinate columns and rows, and no moving slot (an excitation order's state: a
// nonzero row) drives it; the constant slots may.
bool FreeCoordinate(const Eigen::MatrixXd& A, int n, int j) {
  if (!A.block(n + j, 0, 1, 2 * n).isZero(0.0) || !A.block(n, j, n, 1).isZero(0.0) ||
      !A.block(n, n + j, n, 1).isZero(0.0))
    return false;
  for (int s = 2 * n; s < A.rows(); ++s) {
    if (A(n + j, s) != 0.0 && !A.row(s).isZero(0.0)) return false;
  }
  return true;
}

}  // namespace

SpectralDecomposition DecomposeWithFreeBodies(const Eigen::MatrixXd& A, int n, double w_ref,
                                              double horizon, double max_condition) {
  const int m = static_cast<int>(A.rows()), slots = m - 2 * n;
  std::vector<int> coupled, free;
  for (int j = 0; j < n; ++j) (FreeCoordinate(A, n, j) ? free : coupled).push_back(j);
  if (free.empty()) return DecomposeGenerator(A, n, w_ref, horizon, max_condition);

  // The coupled generator: positions, velocities, slots.
  const int p = static_cast<int>(coupled.size()), q = static_cast<int>(free.size());
  const int mc = 2 * p + slots;
  std::vector<int> z_of(static_cast<size_t>(mc));  // core row -> full row
  for (int i = 0; i < p; ++i) {
    z_of[static_cast<size_t>(i)] = coupled[static_cast<size_t>(i)];
    z_of[static_cast<size_t>(p + i)] = n + coupled[static_cast<size_t>(i)];
  }
  for (int s = 0; s < slots; ++s) z_of[static_cast<size_t>(2 * p + s)] = 2 * n + s;
  Eigen::MatrixXd core(mc, mc);
  for (int c = 0; c < mc; ++c) {
    for (int r = 0; r < mc; ++r)
      core(r, c) = A(z_of[static_cast<size_t>(r)], z_of[static_cast<size_t>(c)]);
  }
  const SpectralDecomposition dc = DecomposeGenerator(core, p, w_ref, horizon, max_condition);
  if (dc.info != SpectralDecomposition::Info::kSuccess) return dc;

  // w = [core cluster (k0), free positions (q), free velocities (q), core blocks].
  const int k0 = dc.zero_size, cluster = k0 + 2 * q;
  const auto w_of = [&](int b) { return b < k0 ? b : b + 2 * q; };
  SpectralDecomposition d;
  d.S = Eigen::MatrixXd::Zero(m, m);
  d.S_inv = Eigen::MatrixXd::Zero(m, m);
  for (int b = 0; b < mc; ++b) {
    for (int a = 0; a < mc; ++a) {
      d.S(z_of[static_cast<size_t>(a)], w_of(b)) = dc.S(a, b);
      d.S_inv(w_of(b), z_of[static_cast<size_t>(a)]) = dc.S_inv(b, a);
    }
  }
  d.B0 = Eigen::MatrixXd::Zero(cluster, cluster);
  d.B0.topLeftCorner(k0, k0) = dc.B0;
  for (int j = 0; j < q; ++j) {
    const int body = free[static_cast<size_t>(j)];
    d.S(body, k0 + j) = d.S_inv(k0 + j, body) = 1.0;
    d.S(n + body, k0 + q + j) = d.S_inv(k0 + q + j, n + body) = 1.0;
    d.B0(k0 + j, k0 + q + j) = 1.0;  // x' = v
    // v' = a^T z_slots, z_slots = S_c[slots, cluster] w_cluster (a drives constant slots only).
    for (int s = 0; s < slots; ++s) {
      d.B0.block(k0 + q + j, 0, 1, k0) += A(n + body, 2 * n + s) * dc.S.block(2 * p + s, 0, 1, k0);
    }
  }
  d.zero_size = cluster;
  d.blocks = dc.blocks;
  for (SpectralDecomposition::Block& b : d.blocks) b.start += 2 * q;
  d.block_sigma = dc.block_sigma;
  d.block_omega = dc.block_omega;
  d.condition =
      d.S.cwiseAbs().colwise().sum().maxCoeff() * d.S_inv.cwiseAbs().colwise().sum().maxCoeff();
  // e^{B0 t}: as DecomposeGenerator; the free chains (slot -> v -> x) add at most two powers to
  // the core cluster's nilpotency index (<= k0).
  d.series_terms = ZeroClusterSeriesTerms(d.B0, horizon, k0 + 3);
  d.info = d.series_terms == 0 ? SpectralDecomposition::Info::kSeriesDiverged
                               : SpectralDecomposition::Info::kSuccess;
  return d;
}

}  // namespace gearnvh
