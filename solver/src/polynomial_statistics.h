// Exact statistics of a polynomial output on a chunk [0, L] (solver/exact_recorder.h explains the
// method): closed-form integrals of y and y^2, and certified extrema. Shared by the pair's
// ExactRecorder and the gear trains' TrainRecorder.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "bracketed_newton.h"
#include "gearnvh/solver/trajectory.h"

namespace gearnvh::polynomial_statistics {

inline constexpr int kMaxDegree = 20;

// H_kl = 1 / (k + l + 1) = int_0^1 s^k s^l ds.
inline constexpr auto kHilbert = [] {
  std::array<std::array<double, kMaxDegree + 1>, kMaxDegree + 1> h{};
  for (int k = 0; k <= kMaxDegree; ++k) {
    for (int l = 0; l <= kMaxDegree; ++l) h[k][l] = 1.0 / (k + l + 1);
  }
  return h;
}();

// Coefficients a_0..a_d of p(s) = sum a_k s^k on [0, L].
struct Poly {
  const double* a;
  int d;
  double Value(double s) const {
    double v = a[d];
    for (int k = d - 1; k >= 0; --k) v = v * s + a[k];
    return v;
  }
  double Slope(double s) const {
    if (d == 0) return 0.0;
    double v = d * a[d];
    for (int k = d - 1; k >= 1; --k) v = v * s + k * a[k];
    return v;
  }
  double Curvature(double s) const {
    if (d < 2) return 0.0;
    double v = d * (d - 1) * a[d];
    for (int k = d - 1; k >= 2; --k) v = v * s + k * (k - 1) * a[k];
    return v;
  }
  // int_0^L (p(s) - offset) ds.
  double Integral(double L, double offset) const {
    auto coefficient = [&](int k) { return k == 0 ? a[0] - offset : a[k]; };
    double v = coefficient(d) / (d + 1);
    for (int k = d - 1; k >= 0; --k) v = v * L + coefficient(k) / (k + 1);
    return v * L;
  }
  // int_0^L (p(s) - offset)^2 ds = L c^T H c with c_k = a_k L^k (p on [0, 1]) and H the Hilbert
  // matrix, H_kl = 1 / (k + l + 1): its symmetric half, each row a contiguous product.
  double SquareIntegral(double L, double offset) const {
    double c[kMaxDegree + 1];
    double power = 1.0;
    for (int k = 0; k <= d; ++k, power *= L) c[k] = (k == 0 ? a[0] - offset : a[k]) * power;
    double off_diagonal = 0.0, diagonal = 0.0;
    for (int k = 0; k <= d; ++k) {
      double row = 0.0;
      for (int l = k + 1; l <= d; ++l) row += kHilbert[k][l] * c[l];
      off_diagonal += c[k] * row;
      diagonal += kHilbert[k][k] * c[k] * c[k];
    }
    return (diagonal + 2.0 * off_diagonal) * L;
  }
  // sup |p''| on [0, L].
  double CurvatureBound(double L) const {
    double bound = 0.0, power = 1.0;
    for (int k = 2; k <= d; ++k, power *= L) bound += k * (k - 1) * std::abs(a[k]) * power;
    return bound;
  }
};

// The polynomial of a[0..degree] (degree <= kMaxDegree) without the trailing terms that cannot
// change its value on [0, L].
inline Poly Trimmed(const double* a, int degree, double L) {
  double size = 0.0, power = 1.0;
  double terms[kMaxDegree + 1];
  for (int k = 0; k <= degree; ++k, power *= L) {
    terms[k] = std::abs(a[k]) * power;
    size += terms[k];
  }
  int d = degree;
  while (d > 0 && terms[d] <= 1e-18 * size) --d;
  return {a, d};
}

inline void Consider(OutputStatistics& st, double value, double time, bool want_min) {
  if (value > st.max) st.max = value, st.time_of_max = time;
  if (want_min && value < st.min) st.min = value, st.time_of_min = time;
}

// Every extremum of p on [0, L] that can beat the running ones (see the header).
inline void UpdateExtrema(const Poly& p, double L, double t0, OutputStatistics& st, bool want_min) {
  Consider(st, p.Value(0.0), t0, want_min);
  Consider(st, p.Value(L), t0 + L, want_min);
  if (p.d < 2) return;
  const double b2 = p.CurvatureBound(L);
  constexpr int kMaxDepth = 48;
  auto search = [&](auto&& self, double lo, double hi, double p_lo, double p_hi, double d_lo,
                    double d_hi, int depth) -> void {
    const double width = hi - lo;
    const double slack = 0.125 * b2 * width * width;
    const bool can_max = std::max(p_lo, p_hi) + slack > st.max;
    const bool can_min = want_min && std::min(p_lo, p_hi) - slack < st.min;
    if (!can_max && !can_min) return;
    const bool sign_change = (d_lo > 0.0) != (d_hi > 0.0);
    if (!sign_change && std::abs(d_lo) + std::abs(d_hi) > b2 * width) return;  // monotone
    if (depth >= kMaxDepth) {
      Consider(st, p.Value(0.5 * (lo + hi)), t0 + 0.5 * (lo + hi), want_min);
      return;
    }
    double split = 0.5 * (lo + hi);
    if (sign_change) {
      // p' changes sign: locate the root (a stationary point) and split there.
      const double sign = d_lo <= 0.0 ? 1.0 : -1.0;
      split = BracketedNewton([&](double s) { return sign * p.Slope(s); },
                              [&](double s) { return sign * p.Curvature(s); }, lo, hi,
                              0.5 * (lo + hi), 1e-16 * L);
      split = std::clamp(split, lo, hi);
      if (split <= lo || split >= hi) split = 0.5 * (lo + hi);
    }
    const double p_split = p.Value(split);
    Consider(st, p_split, t0 + split, want_min);
    const double d_split = p.Slope(split);
    self(self, lo, split, p_lo, p_split, d_lo, d_split, depth + 1);
    self(self, split, hi, p_split, p_hi, d_split, d_hi, depth + 1);
  };
  constexpr int kStart = 4;
  double lo = 0.0, p_lo = p.Value(0.0), d_lo = p.Slope(0.0);
  for (int i = 1; i <= kStart; ++i) {
    const double hi = L * i / kStart;
    const double p_hi = p.Value(hi), d_hi = p.Slope(hi);
    search(search, lo, hi, p_lo, p_hi, d_lo, d_hi, 0);
    lo = hi, p_lo = p_hi, d_lo = d_hi;
  }
}

inline void Accumulate(OutputStatistics& st, const Poly& p, double L) {
  if (!st.has_offset) st.offset = p.a[0], st.has_offset = true;
  st.integral += static_cast<long double>(p.Integral(L, st.offset));
  st.square_integral += static_cast<long double>(p.SquareIntegral(L, st.offset));
}

}  // namespace gearnvh::polynomial_statistics
