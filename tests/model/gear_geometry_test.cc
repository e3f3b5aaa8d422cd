#include "gearnvh/model/gear_geometry.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

using testing::StandardPair;

// Closed-form contact ratio of a standard (x = 0, h_a* = 1) pair at the standard centre distance,
// written in units of the module: eps = [sqrt((z1/2+1)^2 - (z1/2 cos a)^2) + (same for z2)
// - (z1+z2)/2 sin a] / (pi cos a).
double StandardContactRatio(int z1, int z2, double alpha) {
  const double r1 = z1 / 2.0, r2 = z2 / 2.0;
  const double c = std::cos(alpha), s = std::sin(alpha);
  return (std::sqrt((r1 + 1) * (r1 + 1) - r1 * r1 * c * c) +
          std::sqrt((r2 + 1) * (r2 + 1) - r2 * r2 * c * c) - (r1 + r2) * s) /
         (std::numbers::pi * c);
}

TEST_CASE("contact ratio of standard 20 degree pairs matches the closed form", "[geometry]") {
  // Tolerance 1e-9: both sides evaluate the same algebra in double precision, differing only in
  // rounding (~1e-15 relative); 1e-9 is the acceptance figure of the issue.
  for (auto [z1, z2] : {std::pair{27, 43}, {20, 20}, {17, 60}, {31, 47}}) {
    const PairGeometry g = ComputePairGeometry(StandardPair(z1, z2));
    CHECK(g.contact_ratio ==
          Approx(StandardContactRatio(z1, z2, 20.0 * std::numbers::pi / 180.0)).epsilon(1e-9));
  }
  // Published value: a 20:20 standard 20-degree pair has eps = 1.557 (e.g. Shigley, ex. 13-x;
  // Maitra, Handbook of Gear Design) to the 3 decimals quoted.
  CHECK(ComputePairGeometry(StandardPair(20, 20)).contact_ratio == Approx(1.557).margin(5e-4));
}

TEST_CASE("standard radii and centre distance", "[geometry]") {
  const GearboxSpec spec = StandardPair(27, 43, 2e-3);
  const PairGeometry g = ComputePairGeometry(spec);
  // Exact identities, tolerance a few ulps of the value (4 * eps relative).
  const double tol = 4 * std::numeric_limits<double>::epsilon();
  CHECK(g.pinion.pitch == Approx(27e-3).epsilon(tol));
  CHECK(g.pinion.tip == Approx(29e-3).epsilon(tol));
  CHECK(g.pinion.root == Approx(24.5e-3).epsilon(tol));
  CHECK(g.wheel.base == Approx(43e-3 * std::cos(20 * std::numbers::pi / 180)).epsilon(tol));
  CHECK(g.center_distance == Approx(70e-3).epsilon(1e-12));  // via the involute inverse
  CHECK(g.working_pressure_angle == Approx(20 * std::numbers::pi / 180).epsilon(1e-10));
  CHECK(g.contact_end - g.contact_start == Approx(g.contact_ratio * g.base_pitch).epsilon(1e-12));
  // Mesh frequency at 800 rpm: z1 n1 / 60 = 360 Hz.
  CHECK(g.mesh_frequency_hz == Approx(360.0).epsilon(1e-12));
}

TEST_CASE("profile-shifted pair uses the zero-backlash working centre distance", "[geometry]") {
  GearboxSpec spec = StandardPair(14, 30, 3e-3);
  spec.pinion.profile_shift = 0.4;
  spec.wheel.profile_shift = 0.1;
  const PairGeometry g = ComputePairGeometry(spec);
  // inv(alpha_w) = inv(alpha0) + 2 (x1+x2) tan(alpha0)/(z1+z2): Newton inverse to ~1e-15.
  const double a0 = 20 * std::numbers::pi / 180;
  CHECK(Involute(g.working_pressure_angle) ==
        Approx(Involute(a0) + 2 * 0.5 * std::tan(a0) / 44).epsilon(1e-12));
  CHECK(g.center_distance ==
        Approx(0.5 * 3e-3 * 44 * std::cos(a0) / std::cos(g.working_pressure_angle)).epsilon(1e-12));
  CHECK(g.center_distance > 0.5 * 3e-3 * 44);
}

TEST_CASE("inverse involute inverts the involute", "[geometry]") {
  for (double a : {0.05, 0.2, 0.349, 0.6, 0.78}) {
    CHECK(InverseInvolute(Involute(a)) == Approx(a).epsilon(1e-13));
  }
}

TEST_CASE("spec validation names the path of the broken rule", "[geometry][validation]") {
  GearboxSpec spec = StandardPair(27, 43);
  spec.mesh.backlash = -1e-5;
  try {
    ValidateGearboxSpec(spec);
    FAIL("negative backlash was accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "mesh.backlash");
    CHECK(std::string(e.what()).find("must be > 0") != std::string::npos);
  }
  spec = StandardPair(27, 43);
  spec.mesh.center_distance = 0.06;  // below r_b1 + r_b2 = 65.8 mm
  CHECK_THROWS_AS(ValidateGearboxSpec(spec), InputError);
  spec = StandardPair(27, 43);
  CHECK_NOTHROW(ValidateGearboxSpec(spec));
}

}  // namespace
}  // namespace gearnvh
