// The first crossing of a polynomial, shared by the V2 searches of the pair (TaylorLocator) and of
// gear trains (TrainStepper): the gap of a Taylor sub-step is p(tau) = sum_k c_k tau^k.
#pragma once

#include <cmath>

#include "bracketed_newton.h"

namespace gearnvh::taylor_root {

// sum_{p > P} q^p / p! <= e^q q^(P+1) / (P+1)!: with ||S A S^-1|| d <= q, the remainder of the
// degree-P Taylor polynomial of e^{A tau} S^-1 (S y) for tau <= d, relative to ||S y||.
inline double Tail(double q, int last_term) {
  double tail = std::exp(q);
  for (int p = 1; p <= last_term + 1; ++p) tail *= q / p;
  return tail;
}

// p(tau) and its first two derivatives (Horner).
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
inline double PolySecondDerivative(const double* c, int degree, double tau) {
  double v = degree * (degree - 1) * c[degree];
  for (int k = degree - 1; k >= 2; --k) v = v * tau + k * (k - 1) * c[k];
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
inline double FirstRoot(const double* c, int degree, double length, int samples) {
  auto p = [&](double t) { return Poly(c, degree, t); };
  auto dp = [&](double t) { return PolyDerivative(c, degree, t); };
  auto ddp = [&](double t) { return PolySecondDerivative(c, degree, t); };
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

}  // namespace gearnvh::taylor_root
