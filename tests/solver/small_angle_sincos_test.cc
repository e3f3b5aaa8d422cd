#include "gearnvh/solver/small_angle_sincos.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <random>

namespace gearnvh {
namespace {

// |computed - exact| in units of the last place of the double nearest to exact, with exact from
// the long double functions (64-bit significand: their own error is ~2^-11 of a double's ulp).
double UlpError(double computed, long double exact) {
  const double nearest = static_cast<double>(exact);
  const double ulp = std::nextafter(std::abs(nearest), std::numeric_limits<double>::infinity()) -
                     std::abs(nearest);
  return static_cast<double>(std::abs(static_cast<long double>(computed) - exact) / ulp);
}

TEST_CASE("small-angle sincos: within 1 ulp of long double sin and cos up to pi/4",
          "[solver][spectral]") {
  // Uniform over [-pi/4, pi/4], log-uniform near 0 (where sin x ~ x tests the relative accuracy)
  // and the end points. Tolerance: 1 ulp, the bound the header states (glibc's own sincos is
  // within 1 ulp; libmvec's vector variants within 4).
  std::mt19937_64 random(21);
  std::uniform_real_distribution<double> uniform(-kSmallAngleLimit, kSmallAngleLimit);
  std::uniform_real_distribution<double> exponent(-30.0, 0.0);
  double worst_sin = 0.0, worst_cos = 0.0;
  auto check = [&](double x) {
    double s = 0.0, c = 0.0;
    SmallAngleSinCos(x, &s, &c);
    worst_sin = std::max(worst_sin, UlpError(s, std::sin(static_cast<long double>(x))));
    worst_cos = std::max(worst_cos, UlpError(c, std::cos(static_cast<long double>(x))));
  };
  for (int i = 0; i < 400000; ++i) check(uniform(random));
  for (int i = 0; i < 100000; ++i) check(std::pow(10.0, exponent(random)));
  for (double x : {0.0, -0.0, kSmallAngleLimit, -kSmallAngleLimit, 1e-300, 5e-324}) check(x);
  INFO("largest error: sin " << worst_sin << " ulp, cos " << worst_cos << " ulp");
  CHECK(worst_sin <= 1.0);
  CHECK(worst_cos <= 1.0);
}

TEST_CASE("small-angle sincos: beyond pi/4 it is glibc's sincos", "[solver][spectral]") {
  for (double x : {std::nextafter(kSmallAngleLimit, 1.0), -1.0, 3.0, 1e5, -7e10}) {
    double s = 0.0, c = 0.0, s_ref = 0.0, c_ref = 0.0;
    SmallAngleSinCos(x, &s, &c);
    sincos(x, &s_ref, &c_ref);
    CHECK(s == s_ref);
    CHECK(c == c_ref);
  }
  double s = 0.0, c = 0.0;
  SmallAngleSinCos(std::numeric_limits<double>::quiet_NaN(), &s, &c);
  CHECK(std::isnan(s));
  CHECK(std::isnan(c));
}

}  // namespace
}  // namespace gearnvh
