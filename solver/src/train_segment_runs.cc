// Segment-run fusion on gear trains (train_segment_runs.h) and the stepper's use of it.
#include "gearnvh/solver/train_segment_runs.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/spectral_gap.h"
#include "gearnvh/solver/train_cycle_map.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_tangents.h"

namespace gearnvh {
namespace {

constexpr int kStateBits = 2;  // per mesh in a combination's code

uint64_t CombinationCode(const std::vector<ContactState>& states) {
  uint64_t code = 0;
  for (ContactState s : states) code = (code << kStateBits) | static_cast<uint64_t>(s);
  return code;
}

// Static equilibrium of a generator (positions; velocity 0; constant slot 1; inputs 0), the free
// rotation pinned (r~ x = 0): least squares, as the initial state.
Eigen::VectorXd Equilibrium(const TrainTables& t, const Eigen::MatrixXd& A) {
  const int n = t.n;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(t.m);
  y[t.constant_slot()] = 1.0;
  Eigen::MatrixXd B(n + 1, n);
  B.topRows(n) = -A.block(n, 0, n, n);
  B.row(n) = std::max(B.topRows(n).norm(), 1.0) / t.recenter_row.norm() * t.recenter_row;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
  rhs.head(n) = A.block(n, t.constant_slot(), n, 1);
  y.head(n) = B.completeOrthogonalDecomposition().solve(rhs);
  return y;
}

// Removes the free rotation from a state: its position, as Recenter does, and its velocity unless
// a drag damps it (then the velocity reaches the other coordinates and is a deviation like any).
void RemoveRigid(const TrainTables& t, Eigen::VectorXd& z) {
  const int n = t.n;
  z.head(n) -= t.recenter_row.dot(z.head(n)) * t.rigid_rotation;
  if (!t.free_rotation_damped) {
    z.segment(n, n) -= t.recenter_row.dot(z.segment(n, n)) * t.rigid_rotation;
  }
}

}  // namespace

TrainSegmentRuns::TrainSegmentRuns(const TrainTables& tables, int max_level, size_t limit_bytes,
                                   long max_period_segments, const std::atomic<bool>* cancel)
    : t_(tables),
      max_level_(max_level),
      limit_bytes_(limit_bytes),
      max_period_segments_(max_period_segments),
      cancel_(cancel),
      walk_(tables) {
  const int meshes = static_cast<int>(tables.meshes.size());
  const int p = tables.m - tables.input_slot();
  const int longest = 1 << max_level;
  enabled_ = tables.common_period > 0.0 && meshes * kStateBits <= 64;
  walls_.reserve(2 * static_cast<size_t>(meshes));
  segments_.resize(static_cast<size_t>(meshes) * longest);
  lengths_.resize(longest);
  inputs_.resize(static_cast<Eigen::Index>(longest) * p);
  abs_inputs_.resize(inputs_.size());
  wall_terms_.resize(2 * meshes, longest);
  slots_.resize(tables.m);
  dev_.resize(tables.m);
  end_.resize(tables.m);
}

TrainSegmentRuns::~TrainSegmentRuns() = default;

void TrainSegmentRuns::ResetBackoff() {
  for (auto& [key, entry] : entries_) entry.skip = entry.backoff = 0;
}

void TrainSegmentRuns::WallsOf(const std::vector<ContactState>& states) {
  walls_.clear();
  for (int j = 0; j < static_cast<int>(states.size()); ++j) {
    switch (states[static_cast<size_t>(j)]) {
      case ContactState::kDrive:
        walls_.push_back({j, true, -1.0});
        break;
      case ContactState::kBack:
        walls_.push_back({j, false, 1.0});
        break;
      case ContactState::kFree:
        walls_.push_back({j, true, 1.0});
        walls_.push_back({j, false, -1.0});
        break;
    }
  }
}

bool TrainSegmentRuns::WalkTo(int count, double end_time) {
  const size_t meshes = t_.meshes.size();
  const int p = t_.m - t_.input_slot();
  while (walked_ < count) {
    if (walk_.end() > end_time) return false;
    const double h = walk_.end() - walk_.start();
    std::copy(walk_.segments().begin(), walk_.segments().end(),
              segments_.begin() + static_cast<std::ptrdiff_t>(walked_ * meshes));
    lengths_[walked_] = h;
    t_.SetInputs(walk_.cycles(), walk_.segments(), walk_.start(), h, end_);
    inputs_.segment(static_cast<Eigen::Index>(walked_) * p, p) = end_.tail(p);
    for (size_t w = 0; w < walls_.size(); ++w) {
      const Wall& wall = walls_[w];
      const int segment = walk_.segments()[static_cast<size_t>(wall.mesh)];
      // The error input's part of the wall (the static part is in the run's constant).
      wall_terms_(static_cast<Eigen::Index>(w), walked_) =
          -wall.sign * (t_.Wall(wall.mesh, segment, wall.drive, end_) -
                        t_.Wall(wall.mesh, segment, wall.drive) * end_[t_.constant_slot()]);
    }
    walk_.Next();
    ++walked_;
  }
  return true;
}

std::unique_ptr<TrainSegmentRuns::Run> TrainSegmentRuns::Build(
    int length, const std::vector<ContactState>& states) {
  const int n = t_.n, m = t_.m, first = t_.input_slot(), p = m - first;
  const int lp = length * p, walls = static_cast<int>(walls_.size());
  const size_t meshes = t_.meshes.size();
  const size_t doubles = static_cast<size_t>(m) * (m + lp + 1) +
                         static_cast<size_t>(walls) * (m + lp + 1) + static_cast<size_t>(length);
  const size_t bytes = doubles * sizeof(double) + meshes * length * sizeof(int);
  if (bytes_ + bytes > limit_bytes_) return nullptr;
  auto run = std::make_unique<Run>();
  run->length = length;
  run->segments.assign(segments_.begin(),
                       segments_.begin() + static_cast<std::ptrdiff_t>(meshes * length));
  run->lengths = lengths_.head(length);
  // Z = [F | G]: the map of Pi z (columns 0..m-1) and of each input set at grid segment i
  // (column m + i p + q) to the state at the current node.
  Eigen::MatrixXd Z = Eigen::MatrixXd::Zero(m, m + lp);
  Z.leftCols(m).setIdentity();
  // Per wall the node maxima: f's constant and weights, and the chord loss's.
  Eigen::VectorXd f_const = Eigen::VectorXd::Constant(walls, -std::numeric_limits<double>::max());
  Eigen::VectorXd loss_const = Eigen::VectorXd::Zero(walls);
  Eigen::MatrixXd f_weights = Eigen::MatrixXd::Zero(walls, m + lp);
  Eigen::MatrixXd loss_weights = Eigen::MatrixXd::Zero(walls, m + lp);
  Eigen::MatrixXd rows(walls, m), curvature_rows(walls, m);
  Eigen::VectorXd third_norms(walls), residual_terms(walls), wall_static(walls), scale(m), Zy(m);
  run->tolerance = Eigen::VectorXd::Zero(walls);
  Eigen::RowVectorXd column_max(m + lp);
  std::vector<int> segments(meshes);
  for (int i = 0; i < length; ++i) {
    ThrowIfCancelled(cancel_);
    std::copy(run->segments.begin() + static_cast<std::ptrdiff_t>(i * meshes),
              run->segments.begin() + static_cast<std::ptrdiff_t>((i + 1) * meshes),
              segments.begin());
    const Eigen::MatrixXd A = AssembleTrainGenerator(t_, segments, states);
    // e_g: this grid segment's equilibrium, A e_g = rho (rounding, and friction's inconsistency
    // along the free rotation); the first one is the run's reference.
    const Eigen::VectorXd equilibrium = Equilibrium(t_, A);
    const Eigen::VectorXd residual = A * equilibrium;
    if (i == 0) run->reference = equilibrium;
    const double w_ref = ReferenceFrequency(A, n);
    scale = BalancingScale(A, n, w_ref);
    const double rate = ScaledRowNorm(A, scale);
    const double residual_norm = scale.cwiseProduct(residual).cwiseAbs().maxCoeff();
    const double h = run->lengths[i];
    const int substeps = std::max(1, static_cast<int>(std::ceil(rate * h)));
    const double d = h / substeps;
    const double growth = std::exp(rate * d);  // ||S e^{As} S^-1||_inf <= e^{q}, q <= 1
    const Eigen::MatrixXd E = BalancedExpm(A, d, n, w_ref);
    const Eigen::MatrixXd full = substeps == 1 ? E : BalancedExpm(A, h, n, w_ref);
    for (int w = 0; w < walls; ++w) {
      const Wall& wall = walls_[static_cast<size_t>(w)];
      const double static_wall =
          t_.Wall(wall.mesh, segments[static_cast<size_t>(wall.mesh)], wall.drive);
      wall_static[w] = -wall.sign * static_wall;
      run->tolerance[w] = std::max(run->tolerance[w], std::abs(static_wall));
      rows.row(w).setZero();
      rows.row(w).head(n) =
          wall.sign * t_.meshes[static_cast<size_t>(wall.mesh)].Vector(wall.drive).transpose();
      curvature_rows.row(w) = rows.row(w) * A * A;
      // ||c A^3 S^-1||_1 without the constant column (z - e_g has no constant part, and e^{As}
      // keeps the slots), and ||c A^2 S^-1||_1 ||S rho||_inf for c A^2 e^{As} rho.
      Eigen::RowVectorXd third =
          (curvature_rows.row(w) * A).cwiseAbs().cwiseQuotient(scale.transpose());
      third[t_.constant_slot()] = 0.0;
      third_norms[w] = third.sum();
      residual_terms[w] =
          curvature_rows.row(w).cwiseAbs().cwiseQuotient(scale.transpose()).sum() * residual_norm;
    }
    // The slots are set at the grid segment's start: cleared in every column, then set.
    Z.bottomRows(p).setZero();
    for (int q = 0; q < p; ++q) Z(first + q, m + i * p + q) = 1.0;
    const Eigen::MatrixXd start = Z;
    for (int k = 0; k <= substeps; ++k) {
      Zy.noalias() = Z.leftCols(m) * run->reference;
      column_max = (scale.asDiagonal() * Z).cwiseAbs().colwise().maxCoeff();
      const double reference_max = scale.cwiseProduct(Zy - equilibrium).cwiseAbs().maxCoeff();
      for (int w = 0; w < walls; ++w) {
        f_const[w] = std::max(f_const[w], rows.row(w).dot(Zy) + wall_static[w]);
        f_weights.row(w) = f_weights.row(w).cwiseMax((rows.row(w) * Z).cwiseAbs());
        if (k == substeps) continue;
        // The chord loss of the sub-step from this node:
        // d^2/8 (|f''| + d e^q (b3 ||S (z - e_g)|| + ||c A^2 S^-1|| ||S rho||)).
        const double factor = d * d / 8.0, reach = d * third_norms[w] * growth;
        loss_const[w] = std::max(loss_const[w],
                                 factor * (std::abs(curvature_rows.row(w).dot(Zy)) +
                                           reach * reference_max + d * growth * residual_terms[w]));
        loss_weights.row(w) = loss_weights.row(w).cwiseMax(
            factor * ((curvature_rows.row(w) * Z).cwiseAbs() + reach * column_max));
      }
      if (k < substeps) Z = (E * Z).eval();
    }
    Z.noalias() = full * start;
  }
  run->product = Z.leftCols(m);
  run->inputs = Z.rightCols(lp);
  for (int w = 0; w < walls; ++w) {
    run->tolerance[w] =
        1e-9 * t_.meshes[static_cast<size_t>(walls_[static_cast<size_t>(w)].mesh)].half_backlash +
        64.0 * std::numeric_limits<double>::epsilon() * run->tolerance[w];
  }
  run->constant = f_const + loss_const;
  const Eigen::MatrixXd weights = f_weights + loss_weights;
  run->weights = weights.leftCols(m);
  run->input_weights = weights.rightCols(lp);
  bytes_ += bytes;
  ++tables_;
  return run;
}

bool TrainSegmentRuns::Nested(const Run& shorter, const Run& run) {
  const auto half = static_cast<std::ptrdiff_t>(shorter.segments.size());
  return std::equal(shorter.segments.begin(), shorter.segments.end(), run.segments.begin(),
                    run.segments.begin() + half) &&
         shorter.lengths == run.lengths.head(shorter.length);
}

bool TrainSegmentRuns::Certify(const Run& run) const {
  const int lp = static_cast<int>(run.input_weights.cols());
  for (size_t w = 0; w < walls_.size(); ++w) {
    const Eigen::Index row = static_cast<Eigen::Index>(w);
    const auto terms = wall_terms_.row(row).head(run.length);
    const double tolerance = run.tolerance[row];
    // Without input slots (no engine order, no errors) the input weights have no columns (and no
    // data to take a row of).
    const double inputs = lp > 0 ? run.input_weights.row(row).dot(abs_inputs_.head(lp)) : 0.0;
    const double reach =
        run.constant[row] + run.weights.row(row).dot(dev_) + inputs + terms.maxCoeff();
    if (!(reach < -tolerance)) return false;
  }
  return true;
}

long TrainSegmentRuns::Advance(long position, const std::vector<ContactState>& states,
                               double end_time, bool build, TrainGrid& grid, Eigen::VectorXd& z) {
  // Nothing held and nothing to build: no cost (not even the period's count, a walk of it).
  if (!enabled_ || (!build && entries_.empty())) return 0;
  if (period_segments_ == 0) {
    period_segments_ = CountCommonPeriodSegments(t_, max_period_segments_ + 1);
    if (period_segments_ > max_period_segments_) enabled_ = false;
  }
  if (!enabled_ || position % 2 != 0 || position + 2 > period_segments_) return 0;
  const Key key{CombinationCode(states), position};
  auto found = entries_.find(key);
  if (found == entries_.end()) {
    if (!build) return 0;
    found = entries_.emplace(key, Entry{}).first;  // the first visit only
    found->second.levels.resize(static_cast<size_t>(max_level_));
  }
  Entry& entry = found->second;
  if (!build && !entry.levels.front()) return 0;
  if (entry.skip > 0) {
    --entry.skip;
    return 0;
  }
  const int p = t_.m - t_.input_slot();
  walk_ = grid;
  walked_ = 0;
  WallsOf(states);
  end_ = z;  // the walk's scratch for SetInputs (its constant slot is 1)
  slots_ = z;
  slots_.tail(p).setZero();  // Pi z
  const Run* chosen = nullptr;
  for (int level = 1; level <= max_level_; ++level) {
    const int r = 1 << level;
    if (position % r != 0 || position + r > period_segments_ || !WalkTo(r, end_time)) break;
    std::unique_ptr<Run>& run = entry.levels[static_cast<size_t>(level - 1)];
    if (!run) {
      if (!build) break;
      run = Build(r, states);
      if (!run) break;  // beyond the tables' limit
      if (level > 1 && Nested(*entry.levels[static_cast<size_t>(level - 2)], *run))
        entry.nested |= 1u << level;
    } else {
      // The period's grid repeats only up to rounding: a held run is used only on the same
      // segments and lengths. The shorter level passed this check on this walk, so a nested run's
      // first half passes it too (see the header): only its second half is compared.
      const int from = (entry.nested >> level & 1u) != 0 ? r / 2 : 0;
      const size_t meshes = t_.meshes.size();
      const auto offset = static_cast<std::ptrdiff_t>(meshes * static_cast<size_t>(from));
      const bool same = std::equal(run->segments.begin() + offset, run->segments.end(),
                                   segments_.begin() + offset) &&
                        ((run->lengths.segment(from, r - from) - lengths_.segment(from, r - from))
                             .cwiseAbs()
                             .array() <= 1e-9 * run->lengths.segment(from, r - from).array())
                            .all();
      if (!same) break;
    }
    dev_ = slots_;
    RemoveRigid(t_, dev_);
    dev_ -= run->reference;
    dev_ = dev_.cwiseAbs();
    abs_inputs_.head(r * p) = inputs_.head(r * p).cwiseAbs();
    if (!Certify(*run)) break;
    chosen = run.get();
  }
  if (chosen == nullptr) {
    entry.backoff = std::min(2 * entry.backoff + 1, kMaxBackoff);
    entry.skip = entry.backoff;
    ++refusals_;
    return 0;
  }
  entry.backoff = 0;
  const int r = chosen->length;
  end_.noalias() = chosen->product * slots_;
  end_.noalias() += chosen->inputs * inputs_.head(r * p);
  z.swap(end_);
  for (int i = 0; i < r; ++i) grid.Next();
  return r;
}

long TrainStepper::FusedRun(double end_time, const TrainRecorder* rec) {
  if (!fusion_ || time_ != grid_.start() || (tangent_ != nullptr && tangent_->active())) return 0;
  // Only on unrecorded time: the run records nothing.
  const double horizon = rec != nullptr ? std::min(end_time, rec->start_time()) : end_time;
  const bool build =
      horizon - time_ >= static_cast<double>(options_.fusion_min_periods) * t_.common_period;
  const long fused = fusion_->Advance(period_position_, states_, horizon, build, grid_, z_);
  if (fused > 0) {
    ++summary_.fused_runs;
    summary_.fused_grid_segments += fused;
  }
  return fused;
}

void TrainStepper::FusionOutcome(TrainStepperSummary& s) const {
  if (!fusion_) return;
  s.fusion_tables = fusion_->tables();
  s.fusion_bytes = fusion_->bytes();
  s.fusion_refusals = fusion_->refusals();
}

}  // namespace gearnvh
