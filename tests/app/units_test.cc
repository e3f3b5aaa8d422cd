#include "config/units.h"

#include <catch2/catch.hpp>
#include <numbers>

namespace gearnvh::config {
namespace {

TEST_CASE("quantities convert to SI", "[units]") {
  // Unit factors are exact decimal or pi-based products: tolerance 2 ulps relative.
  const double tol = 2 * std::numeric_limits<double>::epsilon();
  CHECK(ParseQuantity("2 mm", Dimension::kLength).value_si == Approx(2e-3).epsilon(tol));
  CHECK(ParseQuantity("100 um", Dimension::kLength).value_si == Approx(1e-4).epsilon(tol));
  CHECK(ParseQuantity("2mm", Dimension::kLength).value_si == Approx(2e-3).epsilon(tol));
  CHECK(ParseQuantity("1e-3", Dimension::kLength).value_si == Approx(1e-3).epsilon(tol));
  CHECK(ParseQuantity("1e-3 m", Dimension::kLength).value_si == Approx(1e-3).epsilon(tol));
  CHECK(ParseQuantity("20 deg", Dimension::kAngle).value_si ==
        Approx(20 * std::numbers::pi / 180).epsilon(tol));
  CHECK(ParseQuantity("1500 rpm", Dimension::kAngularSpeed).value_si ==
        Approx(50 * std::numbers::pi).epsilon(tol));
  CHECK(ParseQuantity("206 GPa", Dimension::kPressure).value_si == Approx(206e9).epsilon(tol));
  CHECK(ParseQuantity("3e-4 kg*m^2", Dimension::kInertia).value_si == Approx(3e-4).epsilon(tol));
  CHECK(ParseQuantity("2e8 N/m", Dimension::kStiffness).value_si == Approx(2e8).epsilon(tol));
  CHECK(ParseQuantity("1e4 N*m/rad", Dimension::kRotationalStiffness).value_si == Approx(1e4));
  CHECK(ParseQuantity("800 rad/s^2", Dimension::kAngularAcceleration).value_si == Approx(800));
  CHECK(ParseQuantity("-0.5 N*m", Dimension::kTorque).value_si == Approx(-0.5));
  CHECK(ParseQuantity("1000 N*s/m", Dimension::kDamping).value_si == Approx(1000));
  CHECK(ParseQuantity("7850 kg/m^3", Dimension::kDensity).value_si == Approx(7850));
}

TEST_CASE("bad quantities are rejected with the rule", "[units]") {
  auto err = [](const char* text, Dimension d) { return ParseQuantity(text, d).error; };
  CHECK(err("2 mmm", Dimension::kLength).find("unknown unit 'mmm'") != std::string::npos);
  CHECK(err("2 mmm", Dimension::kLength).find("accepted: m, mm") != std::string::npos);
  CHECK(err("100 rpm", Dimension::kLength).find("unknown unit") != std::string::npos);
  CHECK_FALSE(err("abc", Dimension::kLength).empty());
  CHECK_FALSE(err("", Dimension::kLength).empty());
  CHECK_FALSE(err("1e999 m", Dimension::kLength).empty());
  CHECK_FALSE(err("nan", Dimension::kDimensionless).empty());
  CHECK_FALSE(err("0.3 mm", Dimension::kDimensionless).empty());
  CHECK(err("0.3", Dimension::kDimensionless).empty());
}

}  // namespace
}  // namespace gearnvh::config

namespace gearnvh::config {
namespace {

TEST_CASE("speed and torque are shown in the units the file used", "[units]") {
  const double rpm = 60.0 / (2.0 * std::numbers::pi);
  const DisplayUnit r = DisplayUnitOf("800 rpm", Dimension::kAngularSpeed);
  CHECK(r.symbol == "rpm");
  CHECK(r.per_si == Approx(rpm).epsilon(1e-15));
  CHECK(DisplayUnitOf("800 rev/min", Dimension::kAngularSpeed).symbol == "rpm");
  CHECK(DisplayUnitOf("13 rev/s", Dimension::kAngularSpeed).symbol == "rev/s");
  CHECK(DisplayUnitOf("83.8", Dimension::kAngularSpeed).symbol == "rad/s");  // plain SI
  CHECK(DisplayUnitOf("0.2 N*m", Dimension::kTorque).symbol == "N m");
  CHECK(DisplayUnitOf("0.2 Nm", Dimension::kTorque).symbol == "N m");
  const DisplayUnit mm = DisplayUnitOf("200 N*mm", Dimension::kTorque);
  CHECK(mm.symbol == "N mm");
  CHECK(mm.per_si == 1e3);
  CHECK(DisplayUnitOf("2 kN*m", Dimension::kTorque).symbol == "kN m");
  CHECK(ParseQuantity("2 kN*m", Dimension::kTorque).unit == "kN*m");
  CHECK(ParseQuantity("2", Dimension::kTorque).unit.empty());
}

}  // namespace
}  // namespace gearnvh::config
