// Numbers as the user reads them: significant digits without an exponent in the everyday range,
// and values converted back from SI into the user's unit as written.
#include "display_units.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>

namespace gearnvh::app {
namespace {

TEST_CASE("numbers are shown as an engineer writes them", "[units][display]") {
  CHECK(Significant(12000.0) == "12000");
  CHECK(Significant(10000.0) == "10000");
  CHECK(Significant(12345.6) == "12346");  // the integer part is never rounded away
  CHECK(Significant(700.5) == "700.5");
  CHECK(Significant(0.5) == "0.5");
  CHECK(Significant(9.99996) == "10");
  CHECK(Significant(0.00012345) == "0.0001234");
  CHECK(Significant(-1234.5, 6) == "-1234.5");
  CHECK(Significant(0.0) == "0");
  CHECK(Significant(3e-7) == "3e-07");  // outside the everyday range: as %g
  CHECK(Significant(std::numeric_limits<double>::infinity()) == "inf");
  const DisplayUnit rpm{"rpm", 60.0 / (2.0 * std::numbers::pi)};
  CHECK(Format(12000.0 / rpm.per_si, rpm) == "12000 rpm");
}

TEST_CASE("a speed converted back from rad/s reads as the user wrote it", "[units][display]") {
  const double rad_s = 700.0 * 2.0 * std::numbers::pi / 60.0;
  REQUIRE(rad_s * 60.0 / (2.0 * std::numbers::pi) != 700.0);  // the round trip's rounding
  CHECK(Rpm(rad_s) == 700.0);
  CHECK(AsWritten(0.1 + 0.2) == 0.3);
  CHECK(AsWritten(1234.56789012345) == 1234.56789012);
}

}  // namespace
}  // namespace gearnvh::app
