// Quantity strings of schema gearnvh/1: "2 mm", "20 deg", "1500 rpm", "206 GPa", or a plain number
// (already SI). Each schema key expects one physical dimension; a unit of another dimension, or an
// unknown unit, is an error that lists the accepted units.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh::config {

enum class Dimension {
  kDimensionless,
  kLength,               // m
  kAngle,                // rad
  kAngularSpeed,         // rad/s
  kTorque,               // N m
  kPressure,             // Pa
  kDensity,              // kg/m^3
  kMass,                 // kg
  kInertia,              // kg m^2
  kStiffness,            // N/m
  kRotationalStiffness,  // N m/rad
  kDamping,              // N s/m
  kAngularAcceleration,  // rad/s^2
  kRotationalDamping,    // N m s/rad
};

const char* DimensionName(Dimension d);
// The name with its indefinite article: "a length", "an angle".
std::string DimensionWithArticle(Dimension d);
// The units accepted for a dimension, comma separated (for error messages and docs).
std::string AcceptedUnits(Dimension d);

struct ParsedQuantity {
  double value_si = 0.0;
  std::string unit;   // the unit symbol as written ("" for a plain SI number)
  std::string error;  // empty on success; otherwise the rule broken
};

// Parses "<number> [unit]" into SI. A bare number is taken as SI.
ParsedQuantity ParseQuantity(std::string_view text, Dimension d);

// The unit a speed or torque written as `text` is best shown in: rpm for rpm and rev/min, rev/s,
// rad/s (also for a plain number); N m, N mm, kN m.
DisplayUnit DisplayUnitOf(std::string_view text, Dimension d);

// Strict full-string number parse (no trailing junk, finite).
std::optional<double> ParseNumber(std::string_view text);

}  // namespace gearnvh::config
