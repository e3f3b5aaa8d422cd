// V3's tables of a (segment, state), built on its first visit (spectral_locator.h): the
// decomposition, the closed-form gaps, the padded dense matrices, the carried-segment block (input
// columns, the walls' screens) and the carry matrix with its error bound.
#include <algorithm>
#include <limits>
#include <new>

#include "gearnvh/solver/spectral_locator.h"

namespace gearnvh {

namespace {

// A padded column's length: m rounded up to whole 64-byte lines (8 doubles).
int PaddedSize(int m) {
  constexpr int line = SpectralLocator::kLineDoubles;
  return (m + line - 1) / line * line;
}

}  // namespace

SpectralLocator::SpectralLocator(const SegmentTables& tables, const SolverOptions& options)
    : EventLocator(tables, options),
      max_condition_(options.spectral_max_condition),
      max_carry_error_(options.carry_max_error),
      padded_(PaddedSize(tables.m)),
      block_doubles_(static_cast<size_t>(tables.inputs + 2 * kMaxWalls + tables.m) * padded_),
      curved_doubles_(static_cast<size_t>(ClosedFormGap::kCurvedRows * kMaxWalls) * padded_),
      entry_(Eigen::VectorXd::Zero(padded_)),
      fallback_(tables, options),
      w_(tables.m),
      wt_(tables.m),
      scratch_(tables.m),
      z1_(tables.m),
      carried_(Eigen::VectorXd::Zero(padded_)) {
  systems_.resize(tables.segments());
  w_ref_.assign(tables.segments(), 0.0);
  // Untouched until a pair is visited (a loaded run fills only its contact state's blocks).
  const size_t doubles = 3 * block_doubles_ * static_cast<size_t>(tables.segments());
  blocks_.reset(static_cast<double*>(
      ::operator new (std::max<size_t>(doubles, 1) * sizeof(double), std::align_val_t{64})));
  const size_t curved = 3 * curved_doubles_ * static_cast<size_t>(tables.segments());
  curved_.reset(static_cast<double*>(
      ::operator new (std::max<size_t>(curved, 1) * sizeof(double), std::align_val_t{64})));
  dense_doubles_ = static_cast<size_t>(padded_) * tables.m;
  product_.setZero(padded_);
}

void SpectralLocator::FreeAligned::operator()(double* p) const {
  ::operator delete (p, std::align_val_t{64});
}

SpectralLocator::System& SpectralLocator::Build(int segment, ContactState state) {
  ThrowIfCancelled(cancel_);  // a decomposition per first visit: many in the first cycles
  System& sp = systems_[segment][static_cast<int>(state)];
  sp.built = true;
  // One balancing frequency for all three states of a segment (the same scaling whichever state
  // is visited first).
  double& w_ref = w_ref_[segment];
  if (w_ref == 0.0) w_ref = t_.SegmentReferenceFrequency(segment);
  const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state)];
  sp.decomposition =
      DecomposeGenerator(sys.A, t_.n, w_ref, t_.SegmentLength(segment), max_condition_);
  sp.ok = sp.decomposition.info == SpectralDecomposition::Info::kSuccess;
  if (!sp.ok) {
    ++statistics_.spectral_fallback_systems;
    return sp;
  }
  statistics_.spectral_max_condition =
      std::max(statistics_.spectral_max_condition, sp.decomposition.condition);
  const size_t dense_bytes = sizeof(double) * kDenseMatrices * dense_doubles_;
  sp.dense.reset(static_cast<double*>(::operator new (dense_bytes, std::align_val_t{64})));
  const auto fill_dense = [&](Dense which, const Eigen::MatrixXd& a) {
    Eigen::Map<Eigen::MatrixXd> padded(sp.dense.get() + static_cast<size_t>(which) * dense_doubles_,
                                       padded_, t_.m);
    padded.topRows(t_.m) = a;
    padded.bottomRows(padded_ - t_.m).setZero();
  };
  fill_dense(Dense::kS, sp.decomposition.S);
  fill_dense(Dense::kSInverse, sp.decomposition.S_inv);
  fill_dense(Dense::kPropagator, sys.full);
  for (int g = 0; g < kGapRows; ++g)
    sp.gaps[g] = ClosedFormGap(sp.decomposition, GapRow(sys, g), t_.SegmentLength(segment));
  // The carried-segment block: input columns, the walls' linear screens (BuildCarry adds the
  // carry).
  sp.block =
      blocks_.get() + (static_cast<size_t>(state) * t_.segments() + segment) * block_doubles_;
  std::fill_n(sp.block, block_doubles_, 0.0);
  const int m = t_.m;
  Eigen::Map<Eigen::MatrixXd> columns(sp.block, padded_, t_.inputs + 2 * kMaxWalls);
  for (int q = 0; q < t_.inputs; ++q)
    columns.col(q).head(m) = sp.decomposition.S_inv.col(t_.input_slot(q));
  GapWall walls[kMaxWalls];
  sp.walls = ActiveWalls(sys, state, walls);
  sp.curved =
      curved_.get() + (static_cast<size_t>(state) * t_.segments() + segment) * curved_doubles_;
  std::fill_n(sp.curved, curved_doubles_, 0.0);
  Eigen::Map<Eigen::MatrixXd> curved(sp.curved, padded_, ClosedFormGap::kCurvedRows * kMaxWalls);
  for (int i = 0; i < sp.walls; ++i) {
    const ClosedFormGap& gap = sp.gaps[walls[i].gap];
    columns.col(t_.inputs + 2 * i).head(m) = walls[i].sign * gap.ScreenStartRow().transpose();
    columns.col(t_.inputs + 2 * i + 1).head(m) = gap.ScreenReachRow().transpose();
    for (int k = 0; k < ClosedFormGap::kCurvedRows; ++k) {
      // The value and rate rows times the wall's sign; the weights of |w| as they are.
      const double sign = k < ClosedFormGap::kCurvedSignedRows ? walls[i].sign : 1.0;
      curved.col(ClosedFormGap::kCurvedRows * i + k).head(m) =
          sign * gap.CurvedScreenRow(k).transpose();
    }
  }
  statistics_.table_bytes +=
      2 * sizeof(double) * static_cast<size_t>(m) * m +
      sizeof(double) * (block_doubles_ + curved_doubles_ + kDenseMatrices * dense_doubles_);
  return sp;
}

const double* SpectralLocator::BuildCarry(int segment, ContactState state) {
  System& sp = systems_[segment][static_cast<int>(state)];
  sp.carry_built = true;
  if (max_carry_error_ <= 0.0) return nullptr;
  const int m = t_.m, p = t_.inputs;
  const bool last = segment + 1 == t_.segments();
  const System* next = last ? nullptr : &Prepared(segment + 1, state);
  if (next != nullptr && !next->ok) return nullptr;
  const SpectralDecomposition& d = sp.decomposition;
  // S_j e^{D_j h_j}, column by column (e^{Dh} is block diagonal).
  Eigen::MatrixXd decoupled(m, m);
  Eigen::VectorXd unit = Eigen::VectorXd::Zero(m), column(m), scratch(m);
  for (int k = 0; k < m; ++k) {
    unit[k] = 1.0;
    PropagateDecoupled(d, unit, t_.SegmentLength(segment), column, scratch);
    decoupled.col(k) = column;
    unit[k] = 0.0;
  }
  Eigen::MatrixXd exit = d.S * decoupled;
  auto norm1 = [](const Eigen::MatrixXd& a) { return a.cwiseAbs().colwise().sum().maxCoeff(); };
  double kappa = 0.0;
  Eigen::MatrixXd carry;
  // The bound is taken in balanced coordinates D z (DecompositionScale), where positions,
  // velocities, forcing and the engine orders' responses weigh alike: relative to |D_j z_j|_1, the
  // error of D_{j+1} z_{j+1} is at most (m + 1) eps |D_{j+1} S_{j+1}|_1 |C_j|_1 |S_j^-1 D_j^-1|_1
  // (two rounded products).
  const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state)];
  const Eigen::VectorXd scale = DecompositionScale(sys.A, t_.n, w_ref_[segment]);
  const double from = norm1(d.S_inv * scale.cwiseInverse().asDiagonal());
  if (last) {
    carry = std::move(exit);
    kappa = norm1(scale.asDiagonal() * carry) * from;
  } else {
    exit.bottomRows(p).setZero();  // Pi: the next segment sets its own inputs
    carry = next->decomposition.S_inv * exit;
    const SegmentSystem& to = t_.systems[segment + 1][static_cast<int>(state)];
    const Eigen::VectorXd next_scale = DecompositionScale(to.A, t_.n, w_ref_[segment + 1]);
    kappa = norm1(next_scale.asDiagonal() * next->decomposition.S) * norm1(carry) * from;
  }
  const double bound = (m + 1) * std::numeric_limits<double>::epsilon() * kappa;
  if (!(bound <= max_carry_error_)) return nullptr;
  double* data = CarryData(sp);
  Eigen::Map<Eigen::MatrixXd>(data, padded_, m).topRows(m) = carry;
  sp.carries = true;
  ++statistics_.carried_systems;
  statistics_.carry_error_bound = std::max(statistics_.carry_error_bound, bound);
  return data;
}

}  // namespace gearnvh
