// V2: the Taylor-polynomial event search (event_locator.h).
#include <algorithm>
#include <cmath>

#include "bracketed_newton.h"
#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {
namespace {

// p(tau) = sum_k c_k tau^k and its derivative (Horner).
inline double Poly(const double* c, int degree, double tau) {
  double v = c[degree];
  for (int k = degree - 1; k >= 0; --k) v = v * tau + c[k];
  return v;
}
inline double PolyDerivative(const double* c, int degree, double tau) {
  double v = degree * c[degree];
  for (int k = degree - 1; k >= 1; --k) v = v * tau + k * c[k];
  return v;
}

// Safeguarded Newton on [lo, hi] from the midpoint, to rounding of `scale`.
template <typename F, typename DF>
double Bracketed(F&& f, DF&& df, double lo, double hi, double scale) {
  return BracketedNewton(f, df, lo, hi, 0.5 * (lo + hi), 1e-16 * scale);
}

// First tau in (0, length] where p rises above 0, or -1. p(0) <= 0 is assumed (we start inside).
// The interval is sampled; where no sample is outside, every local maximum between samples
// (p' changing from + to -) is located by Newton on p' and tested, so a brief excursion across
// the wall between samples is not missed.
double FirstRoot(const double* c, int degree, double length, int samples) {
  auto p = [&](double t) { return Poly(c, degree, t); };
  auto dp = [&](double t) { return PolyDerivative(c, degree, t); };
  auto ddp = [&](double t) {
    double v = degree * (degree - 1) * c[degree];
    for (int k = degree - 1; k >= 2; --k) v = v * t + k * (k - 1) * c[k];
    return v;
  };
  double a = 0.0, slope_a = dp(0.0);
  for (int i = 1; i <= samples; ++i) {
    const double b = length * i / samples;
    if (p(b) > 0.0) return Bracketed(p, dp, a, b, length);
    const double slope_b = dp(b);
    if (slope_a > 0.0 && slope_b < 0.0) {
      // A maximum inside (a, b): find it (root of -p'), and if it is outside the wall, the first
      // crossing lies between a and the maximum.
      const double peak = Bracketed([&](double t) { return -dp(t); },
                                    [&](double t) { return -ddp(t); }, a, b, length);
      if (p(peak) > 0.0) return Bracketed(p, dp, a, peak, length);
    }
    a = b;
    slope_a = slope_b;
  }
  return -1.0;
}

}  // namespace

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
