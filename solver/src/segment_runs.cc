#include "gearnvh/solver/segment_runs.h"

#include <cmath>

#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

namespace {

struct WallSpec {
  const Eigen::RowVectorXd* (*row)(const SegmentSystem&);
  double sign;
};

const Eigen::RowVectorXd* DriveRow(const SegmentSystem& s) { return &s.gap_drive; }
const Eigen::RowVectorXd* BackRow(const SegmentSystem& s) { return &s.gap_back; }

std::vector<WallSpec> WallsOf(ContactState state) {
  switch (state) {
    case ContactState::kFree:
      return {{DriveRow, 1.0}, {BackRow, -1.0}};
    case ContactState::kDrive:
      return {{DriveRow, -1.0}};
    case ContactState::kBack:
      return {{BackRow, 1.0}};
  }
  return {};
}

// Static equilibrium of a generator (positions; velocity 0; constant slot 1): least squares with
// the free rotation pinned, as for the initial state. Free flight has none: the constant slot.
Eigen::VectorXd Equilibrium(const SegmentTables& t, const Eigen::MatrixXd& A, ContactState state) {
  const int n = t.n;
  Eigen::VectorXd z = Eigen::VectorXd::Zero(t.m);
  z[2 * n] = 1.0;
  if (state == ContactState::kFree) return z;
  Eigen::MatrixXd B(n + 1, n);
  B.topRows(n) = -A.block(n, 0, n, n);
  const double scale = B.topRows(n).norm() / std::max(t.recenter_row.norm(), 1e-300);
  B.row(n) = t.recenter_row.norm() > 0.0 ? (scale * t.recenter_row).eval()
                                         : Eigen::RowVectorXd::Zero(n).eval();
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
  rhs.head(n) = A.block(n, 2 * n, n, 1);
  z.head(n) = B.colPivHouseholderQr().solve(rhs);
  return z;
}

// Between grid points (spacing d, rho d <= 1/2, rho the spectral radius) |h''| exceeds its grid
// values by at most rho d / 2 of its maximum: M2 <= M2_grid / (1 - 1/4).
constexpr double kGridFactor = 4.0 / 3.0;

}  // namespace

SegmentRunTable::SegmentRunTable(const SegmentTables& t, ContactState state, int max_level,
                                 const std::atomic<bool>* cancel)
    : t_(&t), state_(state), tolerance_(1e-9 * t.half_backlash) {
  const int S = t.segments(), p = t.inputs;
  input_bounds_.resize(p);
  for (int q = 0; q < p; ++q) input_bounds_[q] = t.InputBound(q);
  for (int level = 1; level <= max_level && (1 << level) <= S; ++level)
    runs_.emplace_back(static_cast<size_t>(S / (1 << level)));
  if (runs_.empty()) return;
  // Built up front: the stepping loop must not allocate (a lazy build on a run's first
  // certificate would, at any cycle). The sub-step grid's propagators E_n = substep^n of a
  // segment are the same in every run that contains it: formed once here.
  std::vector<std::vector<Eigen::MatrixXd>> grid(static_cast<size_t>(S));
  for (int k = 0; k < S; ++k) {
    ThrowIfCancelled(cancel);
    const SegmentSystem& sys = t.systems[k][static_cast<int>(state)];
    Eigen::MatrixXd E = Eigen::MatrixXd::Identity(t.m, t.m);
    grid[static_cast<size_t>(k)].push_back(E);
    for (int n = 0; n < t.substeps[k]; ++n) {
      E = (sys.substep * E).eval();
      grid[static_cast<size_t>(k)].push_back(E);
    }
  }
  for (int level = 1; level <= static_cast<int>(runs_.size()); ++level) {
    for (int index = 0; index < static_cast<int>(runs_[static_cast<size_t>(level - 1)].size());
         ++index) {
      ThrowIfCancelled(cancel);
      Build(level, index, grid);
    }
  }
}

const SegmentRun& SegmentRunTable::Run(int level, int index) const {
  return runs_[static_cast<size_t>(level - 1)][static_cast<size_t>(index)];
}

void SegmentRunTable::Build(int level, int index,
                            const std::vector<std::vector<Eigen::MatrixXd>>& grid) {
  SegmentRun& run = runs_[static_cast<size_t>(level - 1)][static_cast<size_t>(index)];
  const SegmentTables& t = *t_;
  const int m = t.m, st = static_cast<int>(state_), p = t.inputs;
  const int constant = t.constant_slot();
  const int r = 1 << level, start = index * r;
  const std::vector<WallSpec> walls = WallsOf(state_);
  run.start = start;
  run.length = r;
  run.duration = t.boundaries[start + r] - t.boundaries[start];
  // F: the map of z (slots cleared) to the state at the current segment start (before its
  // slots are set); g[i p + q]: the state contribution of input q set at segment i there.
  Eigen::MatrixXd F;
  std::vector<Eigen::VectorXd> g;
  int from = start;
  if (level > 1) {
    // The first half is the run of the level below, from the same start: the same products in
    // the same order, so its F, g and grid weights are continued over the second half only.
    const SegmentRun& half = Run(level - 1, 2 * index);
    F = half.product;
    for (int i = 0; i < half.inputs.cols(); ++i) g.emplace_back(half.inputs.col(i));
    run.walls = half.walls;
    from = start + r / 2;
  } else {
    F = Eigen::MatrixXd::Identity(m, m);
  }
  for (size_t i = 0; i < walls.size(); ++i) {
    const WallSpec& w = walls[i];
    Eigen::RowVectorXd c = *w.row(t.systems[start][st]);
    c[constant] = 0.0;
    // Input terms of the gap (the manufacturing error) change per segment like the constant:
    // bounded by their largest value instead of followed.
    double input_reach = 0.0;
    for (int q = 0; q < p; ++q) {
      input_reach += std::abs(c[t.input_slot(q)]) * input_bounds_[q];
      c[t.input_slot(q)] = 0.0;
    }
    if (level == 1) {
      SegmentRun::Wall wall;
      wall.sign = w.sign;
      wall.position_row = w.sign * c;
      wall.rate_row = w.sign * c * t.systems[start][st].A;
      wall.curvature_weights = Eigen::VectorXd::Zero(m);
      wall.input_weights = Eigen::VectorXd::Zero(p);
      wall.reference = Equilibrium(t, t.systems[start][st].A, state_);
      run.walls.push_back(std::move(wall));
    }
    SegmentRun::Wall& wall = run.walls[i];
    wall.constant_max = -1e300;
    for (int k = start; k < start + r; ++k) {
      wall.constant_max =
          std::max(wall.constant_max, w.sign * (*w.row(t.systems[k][st]))[constant]);
    }
    wall.constant_max += input_reach;
  }
  for (int k = from; k < start + r; ++k) {
    const SegmentSystem& sys = t.systems[k][st];
    // The slots are set at the segment start: clear them in F and in earlier contributions
    // (Pi F, row by row).
    for (int q = 0; q < p; ++q) {
      F.row(t.input_slot(q)).setZero();
      for (Eigen::VectorXd& v : g) v[t.input_slot(q)] = 0.0;
    }
    for (int q = 0; q < p; ++q) g.push_back(Eigen::VectorXd::Unit(m, t.input_slot(q)));
    // Sample the curvature rows on the sub-step grid of this segment.
    for (const Eigen::MatrixXd& E : grid[static_cast<size_t>(k)]) {
      for (SegmentRun::Wall& wall : run.walls) {
        const Eigen::RowVectorXd curvature = wall.position_row * sys.A * sys.A * E;
        const Eigen::RowVectorXd on_start = curvature * F;
        wall.curvature_weights = wall.curvature_weights.cwiseMax(on_start.transpose().cwiseAbs());
        wall.reference_curvature =
            std::max(wall.reference_curvature, std::abs(on_start.dot(wall.reference)));
        Eigen::VectorXd per_input = Eigen::VectorXd::Zero(p);
        for (size_t i = 0; i < g.size(); ++i) {
          per_input[static_cast<Eigen::Index>(i) % p] += std::abs(curvature.dot(g[i]));
        }
        wall.input_weights = wall.input_weights.cwiseMax(per_input);
      }
    }
    F = (sys.full * F).eval();
    for (Eigen::VectorXd& v : g) v = sys.full * v;
  }
  run.product = std::move(F);
  run.inputs.resize(m, r * p);
  for (int i = 0; i < r * p; ++i) run.inputs.col(i) = g[static_cast<size_t>(i)];
  bytes_ += sizeof(double) *
            (static_cast<size_t>(run.product.size()) + static_cast<size_t>(run.inputs.size()));
}

const SegmentRun* SegmentRunTable::Certify(int segment, const Eigen::VectorXd& z,
                                           Eigen::VectorXd& scratch) {
  if (runs_.empty() || segment % 2 != 0) return nullptr;
  // |L Pi z|: the elastic state (free rotation removed), slots cleared, constant slot kept.
  scratch = z;
  scratch.tail(t_->inputs).setZero();
  Eigen::Map<Eigen::MatrixXd> as_matrix(scratch.data(), scratch.size(), 1);
  RemoveFreeRotation(*t_, as_matrix);
  // Shortest first: a run's certificate implies that of every shorter run from the same start (the
  // same rows and reference, its weights and constant maxima over a subset of the grid, a shorter
  // duration), so the first refusal ends the search.
  const SegmentRun* longest = nullptr;
  for (int level = 1; level <= static_cast<int>(runs_.size()); ++level) {
    const int r = 1 << level;
    if (segment % r != 0) break;
    const size_t index = static_cast<size_t>(segment / r);
    if (index >= runs_[static_cast<size_t>(level - 1)].size()) break;
    const SegmentRun& run = Run(level, static_cast<int>(index));
    for (const SegmentRun::Wall& w : run.walls) {
      const double h0 = w.position_row.dot(z);
      // The rate at the start: the slots cleared in scratch, their terms bounded by u_max.
      const double h1 = std::abs(w.rate_row.dot(scratch)) +
                        w.rate_row.tail(t_->inputs).cwiseAbs().dot(input_bounds_);
      const double m2 = kGridFactor * (w.reference_curvature +
                                       w.curvature_weights.dot((scratch - w.reference).cwiseAbs()) +
                                       w.input_weights.dot(input_bounds_));
      const double d = run.duration;
      const double reach = h0 + h1 * d + 0.5 * m2 * d * d;
      if (!(reach + w.constant_max < -tolerance_)) return longest;
    }
    longest = &run;
  }
  return longest;
}

size_t SegmentRunTable::bytes() const { return bytes_; }

}  // namespace gearnvh
