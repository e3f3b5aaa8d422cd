// One tuple's tables (train_tables.h): its generator and the dense path's rate bound (Build), its
// decomposition and closed-form gaps (Decompose).
#include <algorithm>
#include <cmath>
#include <vector>

#include "gearnvh/solver/train_tables.h"
#include "train_decomposition.h"

namespace gearnvh {
namespace {

// lambda_max(M^-1 X) from the symmetric M^-1/2 X M^-1/2 (same eigenvalues, cheaper), on the
// coordinates whose row of X is nonzero (the others add zero eigenvalues: at tier 1 the bodies no
// contact couples).
double LargestRate(const Eigen::VectorXd& inv_j, const Eigen::MatrixXd& X) {
  const Eigen::VectorXd root_inv_j = inv_j.cwiseSqrt();
  std::vector<int> rows;
  for (int j = 0; j < X.rows(); ++j) {
    if (!X.row(j).isZero(0.0)) rows.push_back(j);
  }
  if (rows.empty()) return 0.0;
  Eigen::MatrixXd sym;
  if (rows.size() == static_cast<size_t>(X.rows())) {
    sym = root_inv_j.asDiagonal() * X * root_inv_j.asDiagonal();
  } else {
    sym = root_inv_j(rows).asDiagonal() * X(rows, rows) * root_inv_j(rows).asDiagonal();
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sym, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .cwiseAbs()
      .maxCoeff();
}

// Only the structure's C_0 + w G can be skew (the mesh terms are symmetric up to rounding of
// c v_i v_j, which must not switch tier 1 to the looser bound).
bool SkewDamping(const TrainTables& t) {
  const Eigen::MatrixXd& c0 = t.structural_damping;
  return c0.size() > 0 && !(0.5 * (c0 - c0.transpose())).isZero(0.0);
}

}  // namespace

double TrainSystemCache::DampingRate(const std::vector<ContactState>& states,
                                     const Eigen::MatrixXd& C) const {
  const Eigen::VectorXd inv_j = t_.inertia.cwiseInverse();
  const auto rate = [&] {
    if (!SkewDamping(t_)) return LargestRate(inv_j, C);
    const Eigen::MatrixXd& c0 = t_.structural_damping;
    const Eigen::MatrixXd skew = 0.5 * (c0 - c0.transpose());
    const Eigen::VectorXd root_inv_j = inv_j.cwiseSqrt();
    return LargestRate(inv_j, 0.5 * (C + C.transpose())) +
           (root_inv_j.asDiagonal() * skew * root_inv_j.asDiagonal()).norm();
  };
  if (states.size() > 32) return rate();
  uint64_t key = 0;
  for (size_t i = 0; i < states.size(); ++i) key |= static_cast<uint64_t>(states[i]) << (2 * i);
  const auto found = damping_rate_.find(key);
  if (found != damping_rate_.end()) return found->second;
  return damping_rate_.emplace(key, rate()).first->second;
}

TrainSystem TrainSystemCache::Build(const std::vector<int>& segments,
                                    const std::vector<ContactState>& states) const {
  const int n = t_.n, m = t_.m;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n), C = Eigen::MatrixXd::Zero(n, n);
  if (t_.structural_stiffness.size() > 0) K = t_.structural_stiffness;
  if (t_.structural_damping.size() > 0) C = t_.structural_damping;
  Eigen::VectorXd f = t_.force;
  const Eigen::VectorXd inv_j = t_.inertia.cwiseInverse();
  const Eigen::VectorXd root_inv_j = inv_j.cwiseSqrt();
  // Friction's rank-one parts k (u - v) v^T and c (u - v) v^T, kept apart from the symmetric K, C
  // (see the bound below), and the norms |M^-1/2 (u - v)| |M^-1/2 v| summed per unit k and c.
  Eigen::MatrixXd friction_k, friction_c;
  double friction_k_norm = 0.0, friction_c_norm = 0.0;
  TrainSystem s;
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    const TrainMeshTable& mt = t_.meshes[i];
    const int j = segments[i];
    const double e = mt.error[static_cast<size_t>(j)], b = mt.half_backlash;
    if (states[i] != ContactState::kFree) {
      const bool drive = states[i] == ContactState::kDrive;
      const double k =
          drive ? mt.k_drive[static_cast<size_t>(j)] : mt.k_back[static_cast<size_t>(j)];
      const Eigen::VectorXd& v = mt.Vector(drive);
      const Eigen::VectorXd& u = mt.ForceVector(j, drive);
      K += k * v * v.transpose();
      C += mt.damping * v * v.transpose();
      f += k * (drive ? e + b : e - b) * u;
      if (mt.has_friction()) {
        if (friction_k.size() == 0) {
          friction_k = friction_c = Eigen::MatrixXd::Zero(n, n);
        }
        const Eigen::VectorXd slide = u - v;
        friction_k += k * slide * v.transpose();
        friction_c += mt.damping * slide * v.transpose();
        const double norms =
            root_inv_j.cwiseProduct(slide).norm() * root_inv_j.cwiseProduct(v).norm();
        friction_k_norm += k * norms;
        friction_c_norm += mt.damping * norms;
      }
    }
  }
  s.A = Eigen::MatrixXd::Zero(m, m);
  s.A.block(0, n, n, n).setIdentity();
  s.A.block(n, 0, n, n) = -(inv_j.asDiagonal() * K);
  s.A.block(n, n, n, n) = -(inv_j.asDiagonal() * C);
  if (friction_k.size() > 0) {
    s.A.block(n, 0, n, n) -= inv_j.asDiagonal() * friction_k;
    s.A.block(n, n, n, n) -= inv_j.asDiagonal() * friction_c;
  }
  s.A.block(n, t_.constant_slot(), n, 1) = inv_j.cwiseProduct(f);
  s.A.block(n, t_.input_slot(), n, 1) = inv_j.cwiseProduct(t_.excitation_direction);
  t_.AddErrorColumns(segments, states, s.A);
  const double w_stiff = std::sqrt(LargestRate(inv_j, K));
  // An eigenvalue lambda of A (eigenvector [u; lambda u], y = M^1/2 u, |y| = 1) solves
  // lambda^2 + c lambda + k = 0 with c = y^* M^-1/2 C M^-1/2 y and k likewise: real in
  // [0, lambda_max] for symmetric C, K >= 0, so |lambda| <= max(sqrt(k_max), c_max). C's skew
  // part (gyroscopic, reduced tiers) and friction's rank-one terms make c and k complex; then
  // |lambda| <= |c| + sqrt(|k|) (|lambda| = R > |c| + sqrt|k| gives R^2 - |c| R > |k|, which
  // |lambda^2| = |c lambda + k| forbids), with |c| bounded by the symmetric part's lambda_max plus
  // the skew part's norm (DampingRate) plus sum mu c_i |M^-1/2 w| |M^-1/2 v| (each friction term
  // is c (y^* M^-1/2 mu w)(v^T M^-1/2 y)), and |k| likewise.
  double rho = 0.0;
  if (friction_k.size() > 0) {
    rho = std::sqrt(w_stiff * w_stiff + friction_k_norm) + DampingRate(states, C) + friction_c_norm;
  } else {
    rho = SkewDamping(t_) ? w_stiff + DampingRate(states, C)
                          : std::max(w_stiff, DampingRate(states, C));
  }
  // The balance is a scale, not a bound: the symmetric part's frequency (friction moves it by
  // O(mu)).
  s.w_ref = std::max(1.0, w_stiff);  // as ReferenceFrequency(A, n)
  s.balance = BalancingScale(s.A, n, s.w_ref);
  s.rate = ScaledRowNorm(s.A, s.balance);
  s.substep = std::min(rho > 0.0 ? 0.5 / rho : t_.longest_segment,
                       s.rate > 0.0 ? TrainSystem::kMaxDenseStepNorm / s.rate : t_.longest_segment);
  for (int c = 0; c < 2 * n; ++c) {
    if (!s.A.block(n, c, n, 1).isZero(0.0)) s.coupled_columns.push_back(c);
  }
  return s;
}

void TrainSystemCache::Decompose(TrainSystem& s) const {
  const int n = t_.n, m = t_.m;
  s.decomposed = true;
  s.decomposition =
      DecomposeWithFreeBodies(s.A, n, s.w_ref, t_.longest_segment, options_.max_condition);
  s.spectral = s.decomposition.info == SpectralDecomposition::Info::kSuccess &&
               s.decomposition.zero_size > 0;
  if (!s.spectral) {
    s.decomposition = SpectralDecomposition{};  // drop the unusable factors
    return;
  }
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(m);
  s.delta.reserve(t_.meshes.size());
  bool distinct = false;
  for (const TrainMeshTable& mt : t_.meshes) {
    row.head(n) = mt.v.transpose();
    s.delta.emplace_back(s.decomposition, row);
    distinct = distinct || mt.distinct_back;
  }
  if (!distinct) return;
  s.delta_back.reserve(t_.meshes.size());
  for (const TrainMeshTable& mt : t_.meshes) {
    row.head(n) = mt.v_back.transpose();
    s.delta_back.emplace_back(s.decomposition, row);
  }
}

}  // namespace gearnvh
