// One tuple's tables (train_tables.h): its generator and the dense path's sub-step (Build, the
// bound of train_rate_bound.h), its decomposition and closed-form gaps (Decompose).
#include <algorithm>
#include <cmath>
#include <vector>

#include "gearnvh/solver/train_rate_bound.h"
#include "gearnvh/solver/train_tables.h"
#include "train_decomposition.h"

namespace gearnvh {

double TrainSystemCache::DampingRate(const std::vector<ContactState>& states,
                                     const Eigen::MatrixXd& C) const {
  if (states.size() > 32) return DampingRateBound(t_, C);
  uint64_t key = 0;
  for (size_t i = 0; i < states.size(); ++i) key |= static_cast<uint64_t>(states[i]) << (2 * i);
  const auto found = damping_rate_.find(key);
  if (found != damping_rate_.end()) return found->second;
  return damping_rate_.emplace(key, DampingRateBound(t_, C)).first->second;
}

TrainSystem TrainSystemCache::Build(const std::vector<int>& segments,
                                    const std::vector<ContactState>& states) const {
  const int n = t_.n, m = t_.m;
  const TuplePencil p = AssembleTuplePencil(t_, segments, states);
  const Eigen::VectorXd inv_j = t_.inertia.cwiseInverse();
  TrainSystem s;
  s.A = Eigen::MatrixXd::Zero(m, m);
  s.A.block(0, n, n, n).setIdentity();
  s.A.block(n, 0, n, n) = -(inv_j.asDiagonal() * p.K);
  s.A.block(n, n, n, n) = -(inv_j.asDiagonal() * p.C);
  if (p.friction_k.size() > 0) {
    s.A.block(n, 0, n, n) -= inv_j.asDiagonal() * p.friction_k;
    s.A.block(n, n, n, n) -= inv_j.asDiagonal() * p.friction_c;
  }
  s.A.block(n, t_.constant_slot(), n, 1) = inv_j.cwiseProduct(p.force);
  t_.AddExcitationColumns(s.A);
  t_.AddErrorColumns(segments, states, s.A);
  const TupleRateBound bound = BoundTupleRate(t_, p, DampingRate(states, p.C));
  // A is block triangular: its eigenvalues are the structure's and the orders' +-i w_k.
  s.rho = std::max(bound.rho, t_.HighestExcitationFrequency());
  // The balance is a scale, not a bound: the symmetric part's frequency (friction moves it by
  // O(mu)).
  s.w_ref = std::max(1.0, bound.stiffness_frequency);  // as ReferenceFrequency(A, n)
  s.balance = BalancingScale(s.A, n, s.w_ref);
  s.rate = ScaledRowNorm(s.A, s.balance);
  s.substep = std::min(s.rho > 0.0 ? 0.5 / s.rho : t_.longest_segment,
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
