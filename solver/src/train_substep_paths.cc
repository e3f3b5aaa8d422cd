// The train's V2 (Taylor) and V1 (dyadic) pieces (train_stepper.h): the V3 dense fallback and the
// validation baselines.
#include <algorithm>
#include <cmath>
#include <limits>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tangents.h"
#include "taylor_root.h"

namespace gearnvh {
namespace {

// acc += x column over n entries (distinct arrays: the loop vectorises).
void AddScaled(double* __restrict acc, const double* __restrict column, double x, int n) {
  for (int r = 0; r < n; ++r) acc[r] += column[r] * x;
}

}  // namespace

void TrainStepper::TaylorColumns(const TrainSystem& sys) {
  // z_k = A z_{k-1} / k. A = [[0, I, 0, 0], [A_x, A_v, f, D], [0, 0, 0, W]]: positions take the
  // velocities, only the n acceleration rows need a product; the orders' states rotate (W), the
  // constant and error slots stay constant.
  const int n = t_.n, m = t_.m;
  const int first_order = t_.ExcitationSlot(0), orders_end = first_order + t_.excitation_states();
  taylor_.col(0) = z_;
  const double* a = sys.A.data();  // column-major, leading dimension m
  for (int k = 1; k <= kTaylorTerms; ++k) {
    const double inv_k = 1.0 / static_cast<double>(k);
    const double* prev = taylor_.col(k - 1).data();
    double* next = taylor_.col(k).data();
    for (int r = 0; r < n; ++r) next[r] = prev[n + r] * inv_k;
    for (int r = n; r < m; ++r) next[r] = 0.0;
    for (int q = first_order; q < orders_end; q += 2) {
      const double w = sys.A(q, q + 1);
      next[q] = w * prev[q + 1] * inv_k;
      next[q + 1] = -w * prev[q] * inv_k;
    }
    // Only the coupled bodies' columns act (the others are zero); the constant and error slots'
    // columns only act on z itself (the later columns are zero there), the orders' on every term.
    const auto add_column = [&](int c) {
      const double x = prev[c] * inv_k;
      if (x != 0.0) AddScaled(next + n, a + static_cast<size_t>(c) * m + n, x, n);
    };
    for (int c : sys.coupled_columns) add_column(c);
    for (int c = k == 1 ? 2 * n : first_order; c < (k == 1 ? m : orders_end); ++c) add_column(c);
  }
}

double TrainStepper::AdvanceDense(const TrainSystem& sys, double remaining, TrainRecorder* rec) {
  ++summary_.dense_pieces;
  const double d = std::min(remaining, sys.substep);
  TaylorColumns(sys);
  double best = -1.0;
  int best_mesh = -1;
  Wall best_wall;
  double delta[kTaylorTerms + 1], coeff[kTaylorTerms + 1];
  // The Taylor coefficients of the wall's flank row (v_i, or v_back,i for g-); a wall's gap
  // differs from it only in the constant term.
  const auto load_delta = [&](size_t i, bool drive) {
    for (int p = 0; p <= kTaylorTerms; ++p)
      delta[p] = t_.meshes[i].Dot(drive, taylor_.col(p).data());
  };
  // sign * (gap of `wall` of mesh i) as a polynomial in the time into the sub-step.
  const auto load_wall = [&](size_t i, const Wall& wall) {
    const double at = t_.Wall(static_cast<int>(i), grid_.segments()[i], wall.drive);
    for (int p = 0; p <= kTaylorTerms; ++p) coeff[p] = wall.sign * delta[p];
    coeff[0] -= wall.sign * (at * z_[t_.constant_slot()] + t_.ErrorInput(static_cast<int>(i), z_));
  };
  // The polynomial's remainder relative to ||S z|| (balanced max-norm; rate d <= 1.5: < 4.4e-16).
  const double tail = taylor_root::Tail(sys.rate * d, kTaylorTerms) *
                      sys.balance.cwiseProduct(z_).cwiseAbs().maxCoeff();
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    // sum_{p >= 1} |delta_p| d^p + ||v||_1 tail bounds |delta(t) - delta(0)| on [0, d]
    double reach = 0.0;
    Wall walls[2];
    const int count = Walls(static_cast<int>(i), walls);
    for (int k = 0; k < count; ++k) {
      if (k == 0 || t_.meshes[i].distinct_back) {
        load_delta(i, walls[k].drive);
        reach = 0.0;
        double power = 1.0;
        for (int p = 1; p <= kTaylorTerms; ++p) power *= d, reach += std::abs(delta[p]) * power;
        reach += t_.meshes[i].Vector(walls[k].drive).lpNorm<1>() * tail;
      }
      load_wall(i, walls[k]);
      // We start inside: rounding right after a located event counts as inside (a start outside
      // beyond the wall tolerance was switched at the grid segment's start).
      coeff[0] = std::min(coeff[0], 0.0);
      if (coeff[0] + reach <= 0.0) continue;  // certificate: the wall is out of reach
      // Or the gap moves within its rounding only (a body at rest on the wall; as
      // WithinRounding on the closed-form path, train_stepper.cc).
      const double rounding =
          t_.GapTolerance(static_cast<int>(i), grid_.segments()[i], walls[k].drive, z_);
      if (coeff[0] > -rounding && coeff[0] + reach <= rounding) continue;
      const double root = taylor_root::FirstRoot(coeff, kTaylorTerms, d, kRootSamples);
      if (root >= 0.0 && (best < 0.0 || root < best)) {
        best = root, best_mesh = static_cast<int>(i), best_wall = walls[k];
      }
    }
  }
  double advance = best < 0.0 ? d : best;
  bool touch = false;
  if (best > 0.0) {
    // Grazing, as V3: |g'| ~ 0 at the root and the gap curves back inside.
    load_delta(static_cast<size_t>(best_mesh), best_wall.drive);
    load_wall(static_cast<size_t>(best_mesh), best_wall);
    touch = std::abs(taylor_root::PolyDerivative(coeff, kTaylorTerms, best)) <=
                options_.grazing_rate_tolerance &&
            taylor_root::PolySecondDerivative(coeff, kTaylorTerms, best) < 0.0;
    if (touch) advance = std::min(d, best + 1e-12 * t_.longest_segment);
  }
  Record(sys, z_, time_, advance, false, rec);
  TaylorValue(advance, z_);
  const bool tangent = tangent_ != nullptr && tangent_->active();
  if (tangent) tangent_->PropagateTaylor(sys.A, advance);
  if (best < 0.0) return advance;
  if (touch) {
    Graze(best_mesh, time_ + best, rec);
    return advance;
  }
  if (tangent) {
    const size_t i = static_cast<size_t>(best_mesh);
    tangent_->Saltation(best_mesh, grid_.segments()[i], states_[i], best_wall.target, z_);
  }
  Switch(best_mesh, best_wall.target, time_ + advance, rec);
  return advance;
}

TrainStepper::WallHit TrainStepper::Suspect(const Eigen::VectorXd& z, const Eigen::VectorXd& z1,
                                            double walk_cell, bool& turned) const {
  const int n = t_.n;
  WallHit hit;
  turned = false;
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    const TrainMeshTable& mt = t_.meshes[i];
    const int segment = grid_.segments()[i];
    Wall walls[2];
    const int count = Walls(static_cast<int>(i), walls);
    for (int k = 0; k < count; ++k) {
      const Wall& w = walls[k];
      const double outside = w.sign * t_.GapValue(static_cast<int>(i), segment, w.drive, z1);
      const Eigen::VectorXd& v = mt.Vector(w.drive);
      const double rate1 = w.sign * v.dot(z1.segment(n, n));
      // Outside at the end, unless only by the gap's rounding floor while moving inward (as the
      // pair's V1: right after a slow separation the state sits on the wall within rounding).
      if (hit.mesh < 0 && outside > 0.0 &&
          (rate1 > 0.0 || outside > t_.GapTolerance(static_cast<int>(i), segment, w.drive, z1))) {
        hit = {static_cast<int>(i), w.target};
      }
      // Turned towards the wall and back: an interior extremum to look at (in the walk, only one
      // that can reach the wall).
      const double rate0 = w.sign * v.dot(z.segment(n, n));
      if (rate0 > 0.0 && rate1 < 0.0 &&
          (walk_cell == 0.0 || w.sign * t_.GapValue(static_cast<int>(i), segment, w.drive, z) +
                                       2.0 * walk_cell * rate0 >
                                   0.0)) {
        turned = true;
      }
    }
  }
  return hit;
}

bool TrainStepper::BelowGapRounding(const WallHit& hit, const Eigen::VectorXd& z,
                                    const Eigen::VectorXd& z1) const {
  const size_t i = static_cast<size_t>(hit.mesh);
  const ContactState now = states_[i];
  const bool drive =
      now == ContactState::kFree ? hit.target == ContactState::kDrive : now == ContactState::kDrive;
  const int segment = grid_.segments()[i];
  const double change = std::abs(t_.GapValue(hit.mesh, segment, drive, z1) -
                                 t_.GapValue(hit.mesh, segment, drive, z));
  return change <= kResolvableRounding * t_.GapTolerance(hit.mesh, segment, drive, z1);
}

double TrainStepper::AdvanceDyadic(const TrainSystem& sys, double remaining, TrainRecorder* rec) {
  const int n = t_.n;
  const double d = std::min(remaining, sys.substep);
  const double w_ref = sys.w_ref;
  substep_map_ = BalancedExpm(sys.A, d, n, w_ref);
  z1_.noalias() = substep_map_ * z_;
  if (rec != nullptr) TaylorColumns(sys);  // the samples inside the sub-step
  bool turned = false;
  if (Suspect(z_, z1_, 0.0, turned).mesh < 0 && !turned) {
    Record(sys, z_, time_, d, false, rec);
    z_.swap(z1_);
    if (tangent_ != nullptr && tangent_->active()) tangent_->PropagateTaylor(sys.A, d);
    return d;
  }
  ++summary_.dyadic_substeps;
  // Every level straight from the balanced Pade (squaring up from the finest level would amplify
  // rounding by 2^34).
  for (int l = 0; l < kDyadicLevels; ++l) {
    dyadic_levels_[static_cast<size_t>(l)] =
        BalancedExpm(sys.A, d / static_cast<double>(1LL << (l + 1)), n, w_ref);
  }
  const long long cells = 1LL << kDyadicLevels;
  const double cell = d / static_cast<double>(cells);
  long long pos = 0;
  while (pos < cells) {
    // Steps of 2^k cells, k = the trailing zeros of pos (L - 1 at pos = 0): aligned.
    int k = pos == 0 ? kDyadicLevels - 1 : __builtin_ctzll(static_cast<unsigned long long>(pos));
    while (pos + (1LL << k) > cells) --k;
    bool crossed = false;
    while (true) {
      z1_.noalias() = dyadic_levels_[static_cast<size_t>(kDyadicLevels - 1 - k)] * z_;
      ++summary_.dyadic_matvecs;
      const double step = cell * static_cast<double>(1LL << k);
      const WallHit hit = Suspect(z_, z1_, step, turned);
      if (hit.mesh < 0 && !(k > 0 && turned)) break;
      if (k == 0 || (hit.mesh >= 0 && BelowGapRounding(hit, z_, z1_))) {
        crossed = true;
        break;
      }
      --k;  // bisect: try the first half
    }
    pos += 1LL << k;
    if (!crossed) {
      z_.swap(z1_);
      continue;
    }
    // The crossing lies in this cell: the event at its end. Every mesh outside there switches
    // (a cell of d 2^-34 cannot order simultaneous crossings), in the order of the meshes.
    const double advance = static_cast<double>(pos) * cell;
    Record(sys, taylor_.col(0), time_, advance, false, rec);  // z_ has moved: its start
    z_.swap(z1_);
    const bool tangent = tangent_ != nullptr && tangent_->active();
    if (tangent) tangent_->PropagateTaylor(sys.A, advance);
    int switched = 0;  // >= 1: the finest cell ended outside a wall
    for (int guard = 0; guard < static_cast<int>(t_.meshes.size()); ++guard) {
      const WallHit hit = Suspect(z_, z_, cell, turned);
      if (hit.mesh < 0) break;
      if (tangent) {
        const size_t i = static_cast<size_t>(hit.mesh);
        tangent_->Saltation(hit.mesh, grid_.segments()[i], states_[i], hit.target, z_);
      }
      Switch(hit.mesh, hit.target, time_ + advance, rec);
      ++switched;
    }
    if (switched > 1) summary_.simultaneous_events += switched - 1;
    return advance;
  }
  Record(sys, taylor_.col(0), time_, d, false, rec);
  if (tangent_ != nullptr && tangent_->active()) tangent_->PropagateTaylor(sys.A, d);
  return d;
}

}  // namespace gearnvh
