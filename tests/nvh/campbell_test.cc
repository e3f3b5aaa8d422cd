#include "gearnvh/nvh/campbell.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

namespace gearnvh {
namespace {

// A Jeffcott-type rotor: a disk at mid-span of a symmetric shaft, so translation (x, y) and tilt
// (theta_x, theta_y) decouple. Tilt with gyroscopics: It th'' +- Ip Omega th'_other + kt th = 0,
// whirl frequencies omega = (+-Ip Omega + sqrt(Ip^2 Omega^2 + 4 It kt)) / (2 It) (forward +,
// backward -); translation sqrt(k / m) at every speed.
struct Jeffcott {
  double m = 10.0, k = 4e6, It = 0.05, Ip = 0.09, kt = 4e4;
  LinearRotorModel Model() const {
    LinearRotorModel r;
    r.M = Eigen::Vector4d(m, m, It, It).asDiagonal();
    r.K = Eigen::Vector4d(k, k, kt, kt).asDiagonal();
    r.G = Eigen::MatrixXd::Zero(4, 4);
    r.G(2, 3) = Ip;
    r.G(3, 2) = -Ip;
    return r;
  }
  double Forward(double w) const {
    return (Ip * w + std::sqrt(Ip * Ip * w * w + 4 * It * kt)) / (2 * It) / (2 * std::numbers::pi);
  }
  double Backward(double w) const {
    return (-Ip * w + std::sqrt(Ip * Ip * w * w + 4 * It * kt)) / (2 * It) / (2 * std::numbers::pi);
  }
  double Translation() const { return std::sqrt(k / m) / (2 * std::numbers::pi); }
};

TEST_CASE("Jeffcott rotor: forward/backward whirl split matches the closed form",
          "[nvh][campbell]") {
  const Jeffcott j;
  std::vector<double> speeds;
  for (int i = 1; i <= 60; ++i) speeds.push_back(i * 50.0);  // up to 3000 rad/s
  CampbellOptions opt;
  opt.modes = 4;
  const CampbellData d = ComputeCampbell(j.Model(), speeds, {}, opt);
  REQUIRE(d.frequency_hz.size() == 4);
  // Classify tracks by their first-speed frequency: translation (x2), backward tilt, forward tilt.
  // Eigenvalues of a 8x8 non-symmetric eigenproblem: relative accuracy ~1e-12 (cond ~ 1); 1e-9.
  int translation_tracks = 0, forward = -1, backward = -1;
  for (int k = 0; k < 4; ++k) {
    const double f0 = d.frequency_hz[k][0];
    if (std::abs(f0 - j.Translation()) <= 1e-9 * f0) {
      ++translation_tracks;
      // Kept apart at the crossing: the translation track stays flat at every speed.
      for (size_t s = 0; s < speeds.size(); ++s) {
        CHECK(std::abs(d.frequency_hz[k][s] - j.Translation()) <= 1e-9 * j.Translation());
      }
    } else if (std::abs(f0 - j.Forward(speeds[0])) <= 1e-9 * f0) {
      forward = k;
    } else if (std::abs(f0 - j.Backward(speeds[0])) <= 1e-9 * f0) {
      backward = k;
    }
  }
  CHECK(translation_tracks == 2);
  REQUIRE(forward >= 0);
  REQUIRE(backward >= 0);
  for (size_t s = 0; s < speeds.size(); ++s) {
    CHECK(std::abs(d.frequency_hz[forward][s] - j.Forward(speeds[s])) <=
          1e-9 * j.Forward(speeds[s]));
    CHECK(std::abs(d.frequency_hz[backward][s] - j.Backward(speeds[s])) <=
          1e-9 * j.Backward(speeds[s]));
  }
  // The backward tilt mode starts above the translation (142.4 vs 100.7 Hz) and ends below it
  // (41 Hz at 3000 rad/s): the tracks really cross.
  CHECK(j.Backward(speeds.front()) > j.Translation());
  CHECK(j.Backward(speeds.back()) < j.Translation());
}

TEST_CASE("critical speeds are where order lines cross tracked modes", "[nvh][campbell]") {
  const Jeffcott j;
  std::vector<double> speeds;
  for (int i = 1; i <= 200; ++i) speeds.push_back(i * 10.0);
  CampbellOptions opt;
  opt.modes = 4;
  const CampbellData d = ComputeCampbell(j.Model(), speeds, {{"1x", 1.0}}, opt);
  // 1x crosses the translation at Omega = sqrt(k/m) = 632.5 rad/s (twice: x and y) and the
  // forward tilt where omega = Omega: It W^2 - Ip W^2 = kt has no solution for Ip > It; the
  // backward tilt where It W^2 + Ip W^2 = kt: W = sqrt(kt / (It + Ip)) = 534.5 rad/s.
  int translation = 0, backward = 0;
  for (const CriticalSpeed& c : d.critical_speeds) {
    // Linear interpolation between speeds 10 rad/s apart on a line and a smooth curve: the
    // crossing error is O(h^2 f'') ~ 1e-2 rad/s here; 0.05 rad/s.
    if (std::abs(c.speed_rad_s - std::sqrt(j.k / j.m)) <= 0.05) ++translation;
    if (std::abs(c.speed_rad_s - std::sqrt(j.kt / (j.It + j.Ip))) <= 0.05) ++backward;
  }
  CHECK(translation == 2);
  CHECK(backward == 1);
  CHECK(d.critical_speeds.size() == 3);
}

TEST_CASE("gear order lines are mesh orders 1-3 and both shafts' orders 1-2", "[nvh][campbell]") {
  const std::vector<OrderLine> lines = GearOrderLines(27, 43);
  REQUIRE(lines.size() == 7);
  CHECK(lines[0].order == 27.0);
  CHECK(lines[2].order == 81.0);
  CHECK(lines[4].order == Approx(27.0 / 43.0).epsilon(1e-15));
}

}  // namespace
}  // namespace gearnvh
