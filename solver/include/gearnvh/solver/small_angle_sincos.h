// sin and cos of one double without glibc's sincos, for the small phases of the closed-form gaps.
//
// glibc's scalar sincos saves and restores the rounding mode on every call (about a third of its
// time). The phases omega t of a segment's slow terms (tier 1's mesh mode: omega H ~ 0.1-0.5) are
// mostly within pi/4, where the Taylor polynomials to x^17 (sin) and x^18 (cos) are exact to below
// 2^-62 relative, so no argument reduction is needed; larger phases go to glibc's sincos.
// Accuracy within pi/4: at most 1 ulp against a long double reference
// (tests/solver/small_angle_sincos_test.cc); cos uses the split 1 - x^2/2 of fdlibm's kernel so the
// leading subtraction adds no rounding of its own.
#pragma once

#include <cmath>
#include <numbers>

namespace gearnvh {

// Largest |x| the polynomials take.
inline constexpr double kSmallAngleLimit = std::numbers::pi / 4.0;

// Horner's scheme in z over coefficients from the highest power down.
template <int N>
constexpr double HornerInZ(const double (&coefficients)[N], double z) {
  double sum = coefficients[0];
  for (int k = 1; k < N; ++k) sum = sum * z + coefficients[k];
  return sum;
}

inline void SmallAngleSinCos(double x, double* sin_x, double* cos_x) {
  if (!(std::abs(x) <= kSmallAngleLimit)) {
    sincos(x, sin_x, cos_x);
    return;
  }
  // sin x = x + x z S(z), S(z) = -1/3! + z/5! - ... + z^7/17!.
  static constexpr double kSin[] = {
      1.0 / 355687428096000.0, -1.0 / 1307674368000.0, 1.0 / 6227020800.0, -1.0 / 39916800.0,
      1.0 / 362880.0,          -1.0 / 5040.0,          1.0 / 120.0,        -1.0 / 6.0};
  // cos x = (1 - z/2) + z^2 C(z), C(z) = 1/4! - z/6! + ... - z^7/18!.
  static constexpr double kCos[] = {
      -1.0 / 6402373705728000.0, 1.0 / 20922789888000.0, -1.0 / 87178291200.0, 1.0 / 479001600.0,
      -1.0 / 3628800.0,          1.0 / 40320.0,          -1.0 / 720.0,         1.0 / 24.0};
  const double z = x * x;
  *sin_x = x + x * z * HornerInZ(kSin, z);
  // w = 1 - z/2 is rounded; (1 - w) - z/2 is its rounding error exactly (1 - w is exact for w in
  // [1/2, 1]).
  const double half = 0.5 * z, w = 1.0 - half;
  *cos_x = w + (((1.0 - w) - half) + z * z * HornerInZ(kCos, z));
}

}  // namespace gearnvh
