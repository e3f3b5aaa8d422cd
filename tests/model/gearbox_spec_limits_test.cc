// The plausibility and resource limits of a spec: each rule fires just past its bound (and not
// just inside it), names its path, and the tip-thickness rule agrees with the closed form.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

using testing::StandardPair;
using L = GearboxLimits;
using testing::kDeg;

std::string PathOfError(const GearboxSpec& spec) {
  try {
    ValidateGearboxSpec(spec);
  } catch (const InputError& e) {
    return e.path();
  }
  return "";
}

TEST_CASE("limits: a standard pair passes and each rule names its path", "[validation][limits]") {
  CHECK(PathOfError(StandardPair(27, 43)).empty());

  GearboxSpec s = StandardPair(27, 43);
  s.pinion.module = s.wheel.module = 1e300;
  CHECK(PathOfError(s) == "gears.pinion.module");

  // Undercut: z_min = 2 h_a* / sin^2(20 deg) = 17.1; 17 teeth are undercut, 18 are not, and a
  // profile shift of 0.1 lowers z_min to 15.4.
  s = StandardPair(17, 43);
  CHECK(PathOfError(s) == "gears.pinion.teeth");
  s = StandardPair(18, 43);
  CHECK(PathOfError(s).empty());
  s = StandardPair(16, 43);
  s.pinion.profile_shift = 0.1;
  s.wheel.profile_shift = -0.1;
  CHECK(PathOfError(s).empty());

  s = StandardPair(27, 43);
  s.pinion.pressure_angle = s.wheel.pressure_angle = 44.0 * kDeg;
  CHECK(PathOfError(s) == "gears.pinion.pressure_angle");
}

TEST_CASE("limits: the pointed-tooth rule follows the closed-form tip thickness",
          "[validation][limits]") {
  // s_a / m for z teeth, pressure angle a, h_a* = 1, x = 0: d_a (pi/(2z) + inv a - inv a_a) / m.
  auto tip_thickness = [](int z, double a) {
    const double d = z, da = z + 2.0, db = d * std::cos(a);
    const double aa = std::acos(db / da);
    auto inv = [](double t) { return std::tan(t) - t; };
    return da * (std::numbers::pi / (2.0 * z) + inv(a) - inv(aa));
  };
  // For 27 teeth find the pressure angle where s_a = 0.2 m by bisection; just below it passes,
  // just above it is refused.
  double lo = 20.0 * kDeg, hi = 44.0 * kDeg;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (tip_thickness(27, mid) > L::kMinTipThickness ? lo : hi) = mid;
  }
  GearboxSpec s = StandardPair(27, 43);
  s.pinion.pressure_angle = s.wheel.pressure_angle = lo - 0.01 * kDeg;
  const std::string below = PathOfError(s);
  CHECK(below != "gears.pinion.pressure_angle");
  s.pinion.pressure_angle = s.wheel.pressure_angle = lo + 0.01 * kDeg;
  CHECK(PathOfError(s) == "gears.pinion.pressure_angle");
}

TEST_CASE("limits: load, excitation, run length and FE size", "[validation][limits]") {
  GearboxSpec s = StandardPair(27, 43);
  // Tooth load T / (r_wheel b) at the bound: r_wheel = 43 mm, b = 15 mm.
  const double bound = L::kMaxUnitLoad * 0.043 * 0.015;
  s.operating.torque = 0.99 * bound;
  CHECK(PathOfError(s).empty());
  s.operating.torque = 1.01 * bound;
  CHECK(PathOfError(s) == "operating.torque");

  s = StandardPair(27, 43);
  const double omega = s.operating.speed;
  s.operating.excitation.push_back({2.0, 0.99 * 2.0 * omega * omega, 0.0});
  CHECK(PathOfError(s).empty());
  s.operating.excitation[0].amplitude = 1.01 * 2.0 * omega * omega;
  CHECK(PathOfError(s) == "operating.excitation[0].amplitude");

  s = StandardPair(27, 43);
  // 2500 cycles at a 1 h bound: the mesh frequency must be >= 2500 / 3600 Hz.
  const double min_speed = 2.0 * std::numbers::pi * 2500.0 / 3600.0 / 27.0;
  s.operating.speed = 1.01 * min_speed;
  CHECK(PathOfError(s).empty());
  s.operating.speed = 0.99 * min_speed;
  CHECK(PathOfError(s) == "operating.speed");
  s = StandardPair(27, 43);
  s.analysis.cycles = static_cast<int>(L::kMaxRecordedCycles) + 1;
  CHECK(PathOfError(s) == "analysis.cycles");
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

std::string MessageOfError(const GearboxSpec& spec) {
  try {
    ValidateGearboxSpec(spec);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("limits: lengths against the module (backlash, face width, STE, tip relief)",
          "[validation][limits]") {
  // Backlash: at most a quarter of the tooth thickness pi m / 2 = 3.14159 mm at m = 2 mm.
  GearboxSpec s = StandardPair(27, 43);
  s.mesh.backlash = 0.25 * std::numbers::pi * 2e-3 / 2.0 * (1.0 - 1e-12);
  CHECK(PathOfError(s).empty());
  s.mesh.backlash = 80.0;  // "backlash: 80" read as 80 m
  CHECK(MessageOfError(s).rfind("mesh.backlash: must be at most 0.785398 mm, 0.25 of the tooth "
                                "thickness at the pitch circle (pi m / 2 = 3.14159 mm at module "
                                "2 mm)",
                                0) == 0);
  s.mesh.backlash = 80e-3;
  CHECK(PathOfError(s) == "mesh.backlash");

  // Face width: b/m in [0.3, 300], 0.6 to 600 mm at m = 2 mm.
  s = StandardPair(27, 43);
  s.pinion.face_width = 300e-3;  // a wide double-helical gear, b/m = 150
  CHECK(PathOfError(s).empty());
  s.pinion.face_width = 20.0;  // "face_width: 20" read as 20 m
  CHECK(MessageOfError(s).rfind("gears.pinion.face_width: gives b/m = 10000 face widths per "
                                "module; must be in [0.3, 300] (here [0.6, 600] mm)",
                                0) == 0);
  s.pinion.face_width = 0.5e-3;
  CHECK(PathOfError(s) == "gears.pinion.face_width");

  s = StandardPair(27, 43);
  s.mesh.static_transmission_error = {{1e-6, 3e-3}, {0.0, 0.0}};
  CHECK(PathOfError(s) == "mesh.static_transmission_error.amplitudes[1]");
  s = StandardPair(27, 43);
  s.wheel.tip_relief = TipRelief{3e-3, 1e-3};
  CHECK(PathOfError(s) == "gears.wheel.tip_relief.amount");
  s.wheel.tip_relief = TipRelief{20e-6, 1e-3};
  CHECK(PathOfError(s).empty());
}

TEST_CASE("limits: a module out of range is blamed on its gear, not on its mate",
          "[validation][limits]") {
  GearboxSpec s = StandardPair(27, 43);
  s.pinion.module = 2.0;  // "module: 2" on the pinion: the wheel's 2 mm is right
  CHECK(PathOfError(s) == "gears.pinion.module");
}

}  // namespace
}  // namespace gearnvh
