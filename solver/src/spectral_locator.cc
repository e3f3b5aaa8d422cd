// V3: closed-form event location in decoupled coordinates (event_locator.h, spectral_gap.h).
#include <algorithm>
#include <cmath>

#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

SpectralLocator::SpectralLocator(const SegmentTables& tables, const SolverOptions& options)
    : EventLocator(tables, options),
      max_condition_(options.spectral_max_condition),
      fallback_(tables, options),
      w_(tables.m),
      wt_(tables.m),
      scratch_(tables.m),
      z1_(tables.m) {
  systems_.resize(tables.segments());
  w_ref_.assign(tables.segments(), 0.0);
}

SpectralLocator::System& SpectralLocator::Prepared(int segment, ContactState state) {
  System& sp = systems_[segment][static_cast<int>(state)];
  if (sp.built) return sp;
  sp.built = true;
  // One balancing frequency for all three states of a segment (the same scaling whichever state
  // is visited first).
  double& w_ref = w_ref_[segment];
  if (w_ref == 0.0) {
    w_ref = 1.0;
    for (const auto& sys : t_.systems[segment])
      w_ref = std::max(w_ref, ReferenceFrequency(sys.A, t_.n));
  }
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
  for (int g = 0; g < kGapRows; ++g) sp.gaps[g] = ClosedFormGap(sp.decomposition, GapRow(sys, g));
  statistics_.table_bytes += 2 * sizeof(double) * static_cast<size_t>(t_.m) * t_.m;
  return sp;
}

bool SpectralLocator::DoStep(int segment, double start, LocatorState& state,
                             EventHandler& handler) {
  const double h = t_.SegmentLength(segment);
  if (!SwitchIfOutsideAtStart(segment, start, state, handler)) return false;
  double done = 0.0;
  bool moved = false;  // z was advanced inside this segment (the full propagator no longer fits)
  Eigen::VectorXd& z = state.z;
  while (true) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    System& sp = Prepared(segment, state.contact);
    if (!sp.ok) return fallback_.AdvanceFrom(segment, start, done, state, handler);
    const double remaining = h - done;
    w_.noalias() = sp.decomposition.S_inv * z;
    ++state.matvecs;
    GapWall walls[kMaxWalls];
    const int count = ActiveWalls(sys, state.contact, walls);
    double best = -1.0;
    int best_wall = -1;
    for (int i = 0; i < count; ++i) {
      ClosedFormGap& gap = sp.gaps[walls[i].gap];
      gap.Load(w_);
      const double root = gap.FirstRise(walls[i].sign, remaining);
      if (root >= 0.0 && (best < 0.0 || root < best)) best = root, best_wall = i;
    }
    if (best < 0.0) {
      if (!moved) {
        z1_.noalias() = sys.full * z;  // the dense propagator: exact to rounding, cond-free
        if (state.tangent != nullptr) state.tangent->Propagate(sys.full);
      } else {
        PropagateDecoupled(sp.decomposition, w_, remaining, wt_, scratch_);
        z1_.noalias() = sp.decomposition.S * wt_;
        if (state.tangent != nullptr)
          state.tangent->PropagateDecoupled(sp.decomposition, remaining);
      }
      z.swap(z1_);
      ++state.matvecs;
      return true;
    }
    const GapWall& w = walls[best_wall];
    ClosedFormGap& gap = sp.gaps[w.gap];
    double step = best;
    const double rate = gap.Rate(best);
    const bool touch = best > 0.0 && std::abs(rate) <= grazing_rate_tolerance_ &&
                       w.sign * gap.Curvature(best) < 0.0;
    // A grazing touch keeps the state; the search resumes just past it.
    if (touch) step = std::min(remaining, best + 1e-12 * h);
    PropagateDecoupled(sp.decomposition, w_, step, wt_, scratch_);
    z.noalias() = sp.decomposition.S * wt_;
    if (state.tangent != nullptr) state.tangent->PropagateDecoupled(sp.decomposition, step);
    ++state.matvecs;
    moved = true;
    done += step;
    if (touch) {
      if (!handler.Graze(start + done)) return false;
    } else if (!handler.Switch(segment, sys, w, start + done, /*state_triggered=*/true)) {
      return false;
    }
    if (h - done <= 1e-15 * h) return true;
  }
}

}  // namespace gearnvh
