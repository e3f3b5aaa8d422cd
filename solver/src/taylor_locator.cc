// V2: the Taylor-polynomial event search (event_locator.h).
#include <algorithm>
#include <cmath>

#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/tangent_propagator.h"
#include "taylor_root.h"

namespace gearnvh {

using taylor_root::FirstRoot;

static_assert(TaylorLocator::kTaylorTerms == TangentPropagator::kTaylorTerms,
              "the tangent follows the state's Taylor series");

TaylorLocator::TaylorLocator(const SegmentTables& tables, const SolverOptions& options)
    : SubstepLocator(tables, options), taylor_(tables.m, kTaylorTerms + 1) {}

bool TaylorLocator::Examine(int segment, double start, LocatorState& state, EventHandler& handler) {
  return Search(segment, start, t_.SegmentLength(segment) / t_.substeps[segment], state, handler);
}

bool TaylorLocator::AdvanceFrom(int segment, double start, double done, LocatorState& state,
                                EventHandler& handler) {
  const double h = t_.SegmentLength(segment);
  const double d = h / t_.substeps[segment];
  while (h - done > 1e-15 * h) {
    const double length = std::min(d, h - done);
    if (!Search(segment, start + done, length, state, handler)) return false;
    done += length;
  }
  return true;
}

bool TaylorLocator::Search(int segment, double start, double length, LocatorState& state,
                           EventHandler& handler) {
  double done = 0.0;
  double coeff[kTaylorTerms + 1];
  Eigen::VectorXd& z = state.z;
  while (length - done > 1e-15 * length) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    taylor_.col(0) = z;
    for (int k = 1; k <= kTaylorTerms; ++k) {
      taylor_.col(k).noalias() = sys.A * taylor_.col(k - 1);
      taylor_.col(k) /= static_cast<double>(k);
    }
    state.matvecs += kTaylorTerms;
    const double remaining = length - done;
    GapWall walls[kMaxWalls];
    const int count = ActiveWalls(sys, state.contact, walls);
    double best = -1.0;
    int best_wall = -1;
    bool outside_at_start[kMaxWalls] = {false, false};
    for (int i = 0; i < count; ++i) {
      for (int k = 0; k <= kTaylorTerms; ++k)
        coeff[k] = walls[i].sign * walls[i].row->dot(taylor_.col(k));
      // Already outside (the unloaded error jumped at a segment boundary): the contact state is
      // the gap's sign, so the event is now. Within rounding of the wall (just after a located
      // event) we count as inside.
      double root = 0.0;
      outside_at_start[i] = BeyondTolerance(coeff[0], *walls[i].row, z);
      if (!outside_at_start[i]) {
        coeff[0] = std::min(coeff[0], 0.0);
        root = FirstRoot(coeff, kTaylorTerms, remaining, kRootSamples);
      }
      if (root >= 0.0 && (best < 0.0 || root < best)) best = root, best_wall = i;
    }
    const double step = best >= 0.0 ? best : remaining;
    if (state.tangent != nullptr && step > 0.0) state.tangent->PropagateTaylor(sys.A, step);
    // z <- sum_k w_k step^k (Horner over the columns).
    z = taylor_.col(kTaylorTerms);
    for (int k = kTaylorTerms - 1; k >= 0; --k) {
      z *= step;
      z += taylor_.col(k);
    }
    done += step;
    if (best < 0.0) break;
    const GapWall& w = walls[best_wall];
    const double rate = w.rate->dot(z);
    if (best > 0.0 && std::abs(rate) <= grazing_rate_tolerance_) {
      // |g'| ~ 0 at the wall. Curving back inside (h'' < 0): a touch, the state is kept and the
      // search resumes just past it. Otherwise it is a tangential crossing and the state flips.
      for (int k = 0; k <= kTaylorTerms; ++k) coeff[k] = w.sign * w.row->dot(taylor_.col(k));
      double curvature = 0.0, power = 1.0;
      for (int k = 2; k <= kTaylorTerms; ++k, power *= step)
        curvature += k * (k - 1) * coeff[k] * power;
      if (curvature < 0.0) {
        if (!handler.Graze(start + done)) return false;
        done = std::min(length, done + 1e-12 * length);
        continue;
      }
    }
    if (!handler.Switch(segment, sys, w, start + done, !outside_at_start[best_wall])) return false;
  }
  return true;
}

}  // namespace gearnvh
