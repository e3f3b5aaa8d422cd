// Safeguarded Newton iteration shared by the V2 (Taylor polynomial) and V3 (closed-form gap)
// event locators.
#pragma once

#include <cmath>

namespace gearnvh {

// Root of f on [lo, hi] with f(lo) <= 0 < f(hi), starting at x0 (the midpoint when x0 is not
// inside). `jet(x)` returns {f(x), f'(x)} (members value and rate), evaluated together because
// they share their costly parts. A Newton step leaving the bracket is replaced by bisection.
// Converged when the step or the bracket is below `tolerance`: returns the step's target, or hi
// when the bracket collapsed (hi is a point known to be past the root).
template <typename Jet>
double BracketedNewtonJet(Jet&& jet, double lo, double hi, double x0, double tolerance,
                          int max_iterations = 200) {
  double x = (x0 > lo && x0 < hi) ? x0 : 0.5 * (lo + hi);
  for (int it = 0; it < max_iterations; ++it) {
    const auto at = jet(x);
    if (at.value > 0.0)
      hi = x;
    else
      lo = x;
    double next = at.rate != 0.0 ? x - at.value / at.rate : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (hi - lo <= tolerance) return hi;
    if (std::abs(next - x) <= tolerance) return next;
    x = next;
  }
  return hi;
}

// The same with f and f' given apart.
template <typename F, typename DF>
double BracketedNewton(F&& f, DF&& df, double lo, double hi, double x0, double tolerance,
                       int max_iterations = 200) {
  struct At {
    double value, rate;
  };
  return BracketedNewtonJet(
      [&](double x) {
        return At{f(x), df(x)};
      },
      lo, hi, x0, tolerance, max_iterations);
}

}  // namespace gearnvh
