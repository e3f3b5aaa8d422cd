#include "gearnvh/solver/segment_runs.h"

#include <cmath>

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

SegmentRunTable::SegmentRunTable(const SegmentTables& t, ContactState state, int max_level)
    : t_(&t), tolerance_(1e-9 * t.half_backlash) {
  const int m = t.m, S = t.segments(), st = static_cast<int>(state);
  const int constant = 2 * t.n, slot = m - 1;
  Eigen::MatrixXd clear = Eigen::MatrixXd::Identity(m, m);
  clear(slot, slot) = 0.0;
  const std::vector<WallSpec> walls = WallsOf(state);
  for (int level = 1; level <= max_level && (1 << level) <= S; ++level) {
    const int r = 1 << level;
    std::vector<SegmentRun> runs;
    for (int start = 0; start + r <= S; start += r) {
      SegmentRun run;
      run.start = start;
      run.length = r;
      run.duration = t.boundaries[start + r] - t.boundaries[start];
      run.excitation = Eigen::MatrixXd::Zero(m, r);
      // F: the map of z (slot cleared) to the state at the current segment start (before its
      // slot is set); g_i: the state contribution of s_i there.
      Eigen::MatrixXd F = Eigen::MatrixXd::Identity(m, m);
      std::vector<Eigen::VectorXd> g;
      for (const WallSpec& w : walls) {
        SegmentRun::Wall wall;
        wall.sign = w.sign;
        Eigen::RowVectorXd c = *w.row(t.systems[start][st]);
        c[constant] = 0.0;
        wall.position_row = w.sign * c;
        wall.rate_row = w.sign * c * t.systems[start][st].A;
        wall.curvature_weights = Eigen::VectorXd::Zero(m);
        wall.reference = Equilibrium(t, t.systems[start][st].A, state);
        wall.constant_max = -1e300;
        for (int k = start; k < start + r; ++k) {
          wall.constant_max =
              std::max(wall.constant_max, w.sign * (*w.row(t.systems[k][st]))[constant]);
        }
        run.walls.push_back(std::move(wall));
      }
      for (int k = start; k < start + r; ++k) {
        const SegmentSystem& sys = t.systems[k][st];
        // The slot is set at the segment start: clear it in F and in earlier contributions.
        F = (clear * F).eval();
        for (Eigen::VectorXd& v : g) v = clear * v;
        g.push_back(Eigen::VectorXd::Unit(m, slot));
        // Sample the curvature rows on the sub-step grid of this segment.
        Eigen::MatrixXd E = Eigen::MatrixXd::Identity(m, m);
        for (int n = 0; n <= t.substeps[k]; ++n) {
          for (size_t w = 0; w < run.walls.size(); ++w) {
            SegmentRun::Wall& wall = run.walls[w];
            const Eigen::RowVectorXd curvature = wall.position_row * sys.A * sys.A * E;
            const Eigen::RowVectorXd on_start = curvature * F;
            wall.curvature_weights = wall.curvature_weights.cwiseMax(on_start.transpose().cwiseAbs());
            wall.reference_curvature =
                std::max(wall.reference_curvature, std::abs(on_start.dot(wall.reference)));
            double excitation = 0.0;
            for (const Eigen::VectorXd& v : g) excitation += std::abs(curvature.dot(v));
            wall.excitation_weight = std::max(wall.excitation_weight, excitation);
          }
          if (n < t.substeps[k]) E = (sys.substep * E).eval();
        }
        F = (sys.full * F).eval();
        for (Eigen::VectorXd& v : g) v = sys.full * v;
      }
      run.product = F;
      for (int i = 0; i < r; ++i) run.excitation.col(i) = g[static_cast<size_t>(i)];
      runs.push_back(std::move(run));
    }
    runs_.push_back(std::move(runs));
  }
}

const SegmentRun* SegmentRunTable::Certify(int segment, const Eigen::VectorXd& z,
                                           double excitation_bound,
                                           Eigen::VectorXd& scratch) const {
  if (runs_.empty()) return nullptr;
  // |L Pi z|: the elastic state (free rotation removed), slot cleared, constant slot kept.
  scratch = z;
  scratch[t_->m - 1] = 0.0;
  Eigen::Map<Eigen::MatrixXd> as_matrix(scratch.data(), scratch.size(), 1);
  RemoveFreeRotation(*t_, as_matrix);
  for (int level = static_cast<int>(runs_.size()); level >= 1; --level) {
    const int r = 1 << level;
    if (segment % r != 0) continue;
    const auto& runs = runs_[static_cast<size_t>(level - 1)];
    const size_t index = static_cast<size_t>(segment / r);
    if (index >= runs.size()) continue;
    const SegmentRun& run = runs[index];
    bool certified = true;
    for (const SegmentRun::Wall& w : run.walls) {
      const double h0 = w.position_row.dot(z);
      // The rate at the start: the slot cleared in scratch, its term bounded by s_max.
      const double h1 = std::abs(w.rate_row.dot(scratch)) +
                        std::abs(w.rate_row[t_->m - 1]) * excitation_bound;
      const double m2 =
          kGridFactor * (w.reference_curvature +
                 w.curvature_weights.dot((scratch - w.reference).cwiseAbs()) +
                 w.excitation_weight * excitation_bound);
      const double d = run.duration;
      const double reach = h0 + h1 * d + 0.5 * m2 * d * d;
      if (!(reach + w.constant_max < -tolerance_)) {
        certified = false;
        break;
      }
    }
    if (certified) return &run;
  }
  return nullptr;
}

size_t SegmentRunTable::bytes() const {
  size_t total = 0;
  for (const auto& level : runs_) {
    for (const SegmentRun& run : level) {
      total += sizeof(double) * (static_cast<size_t>(run.product.size()) +
                                 static_cast<size_t>(run.excitation.size()));
    }
  }
  return total;
}

}  // namespace gearnvh
