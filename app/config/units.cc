#include "units.h"

#include <charconv>
#include <cmath>
#include <numbers>
#include <vector>

namespace gearnvh::config {
namespace {

struct UnitEntry {
  const char* symbol;
  double to_si;
};

const std::vector<UnitEntry>& Table(Dimension d) {
  constexpr double kPi = std::numbers::pi;
  static const std::vector<UnitEntry> none{};
  static const std::vector<UnitEntry> length{{"m", 1.0},   {"mm", 1e-3}, {"cm", 1e-2},
                                             {"um", 1e-6}, {"µm", 1e-6}, {"in", 0.0254}};
  static const std::vector<UnitEntry> angle{{"rad", 1.0}, {"deg", kPi / 180.0}, {"°", kPi / 180.0}};
  static const std::vector<UnitEntry> speed{{"rad/s", 1.0},
                                            {"rpm", 2.0 * kPi / 60.0},
                                            {"rev/min", 2.0 * kPi / 60.0},
                                            {"rev/s", 2.0 * kPi}};
  static const std::vector<UnitEntry> torque{
      {"N*m", 1.0}, {"Nm", 1.0}, {"N.m", 1.0}, {"N*mm", 1e-3}, {"kN*m", 1e3}};
  static const std::vector<UnitEntry> pressure{{"Pa", 1.0},  {"kPa", 1e3},   {"MPa", 1e6},
                                               {"GPa", 1e9}, {"N/m^2", 1.0}, {"N/mm^2", 1e6}};
  static const std::vector<UnitEntry> density{{"kg/m^3", 1.0}, {"g/cm^3", 1e3}, {"kg/dm^3", 1e3}};
  static const std::vector<UnitEntry> mass{{"kg", 1.0}, {"g", 1e-3}};
  static const std::vector<UnitEntry> inertia{
      {"kg*m^2", 1.0}, {"kg*mm^2", 1e-6}, {"kg*cm^2", 1e-4}, {"g*mm^2", 1e-9}, {"g*cm^2", 1e-7}};
  static const std::vector<UnitEntry> stiffness{{"N/m", 1.0},   {"N/mm", 1e3}, {"N/um", 1e6},
                                                {"kN/mm", 1e6}, {"MN/m", 1e6}, {"GN/m", 1e9}};
  // Spelt as torque is (N*m, Nm, N.m): a damper rate from a drawing is often "Nm/deg".
  static const std::vector<UnitEntry> rot_stiffness{
      {"N*m/rad", 1.0},          {"Nm/rad", 1.0},         {"N.m/rad", 1.0},
      {"kN*m/rad", 1e3},         {"kNm/rad", 1e3},        {"N*mm/rad", 1e-3},
      {"N*m/deg", 180.0 / kPi},  {"Nm/deg", 180.0 / kPi}, {"N.m/deg", 180.0 / kPi},
      {"kN*m/deg", 180e3 / kPi}, {"kNm/deg", 180e3 / kPi}};
  static const std::vector<UnitEntry> damping{{"N*s/m", 1.0}, {"kN*s/m", 1e3}, {"N*s/mm", 1e3}};
  static const std::vector<UnitEntry> accel{{"rad/s^2", 1.0}, {"krad/s^2", 1e3}};
  static const std::vector<UnitEntry> rot_damping{
      {"N*m*s/rad", 1.0},   {"Nms/rad", 1.0},           {"N.m.s/rad", 1.0},
      {"N*mm*s/rad", 1e-3}, {"N*m*s/deg", 180.0 / kPi}, {"Nms/deg", 180.0 / kPi}};
  switch (d) {
    case Dimension::kDimensionless:
      return none;
    case Dimension::kLength:
      return length;
    case Dimension::kAngle:
      return angle;
    case Dimension::kAngularSpeed:
      return speed;
    case Dimension::kTorque:
      return torque;
    case Dimension::kPressure:
      return pressure;
    case Dimension::kDensity:
      return density;
    case Dimension::kMass:
      return mass;
    case Dimension::kInertia:
      return inertia;
    case Dimension::kStiffness:
      return stiffness;
    case Dimension::kRotationalStiffness:
      return rot_stiffness;
    case Dimension::kDamping:
      return damping;
    case Dimension::kAngularAcceleration:
      return accel;
    case Dimension::kRotationalDamping:
      return rot_damping;
  }
  return none;
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::string DimensionWithArticle(Dimension d) {
  const std::string name = DimensionName(d);
  return (name.find_first_of("aeiou") == 0 ? "an " : "a ") + name;
}

const char* DimensionName(Dimension d) {
  switch (d) {
    case Dimension::kDimensionless:
      return "dimensionless number";
    case Dimension::kLength:
      return "length";
    case Dimension::kAngle:
      return "angle";
    case Dimension::kAngularSpeed:
      return "rotational speed";
    case Dimension::kTorque:
      return "torque";
    case Dimension::kPressure:
      return "pressure";
    case Dimension::kDensity:
      return "density";
    case Dimension::kMass:
      return "mass";
    case Dimension::kInertia:
      return "moment of inertia";
    case Dimension::kStiffness:
      return "stiffness";
    case Dimension::kRotationalStiffness:
      return "rotational stiffness";
    case Dimension::kDamping:
      return "damping";
    case Dimension::kAngularAcceleration:
      return "angular acceleration";
    case Dimension::kRotationalDamping:
      return "rotational damping";
  }
  return "quantity";
}

std::string AcceptedUnits(Dimension d) {
  std::string out;
  for (const auto& u : Table(d)) {
    if (!out.empty()) out += ", ";
    out += u.symbol;
  }
  return out.empty() ? "none (a plain number)" : out;
}

std::optional<double> ParseNumber(std::string_view text) {
  text = Trim(text);
  if (text.empty()) return std::nullopt;
  if (text.front() == '+') text.remove_prefix(1);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

DisplayUnit DisplayUnitOf(std::string_view text, Dimension d) {
  const std::string unit = ParseQuantity(text, d).unit;
  if (d == Dimension::kAngularSpeed) {
    if (unit == "rpm" || unit == "rev/min") return {"rpm", 60.0 / (2.0 * std::numbers::pi)};
    if (unit == "rev/s") return {"rev/s", 1.0 / (2.0 * std::numbers::pi)};
    return {"rad/s", 1.0};
  }
  if (d == Dimension::kTorque) {
    if (unit == "N*mm") return {"N mm", 1e3};
    if (unit == "kN*m") return {"kN m", 1e-3};
    return {"N m", 1.0};
  }
  if (d == Dimension::kRotationalDamping) {
    if (unit == "N*mm*s/rad") return {"N mm s/rad", 1e3};
    if (unit == "N*m*s/deg" || unit == "Nms/deg") return {"N m s/deg", std::numbers::pi / 180.0};
    return {"N m s/rad", 1.0};
  }
  if (d == Dimension::kRotationalStiffness) {
    if (unit == "kN*m/rad" || unit == "kNm/rad") return {"kN m/rad", 1e-3};
    if (unit == "N*mm/rad") return {"N mm/rad", 1e3};
    if (unit == "N*m/deg" || unit == "Nm/deg" || unit == "N.m/deg")
      return {"N m/deg", std::numbers::pi / 180.0};
    if (unit == "kN*m/deg" || unit == "kNm/deg") return {"kN m/deg", std::numbers::pi / 180e3};
    return {"N m/rad", 1.0};
  }
  // Any other dimension: the unit as written, SI (the table's first unit) for a plain number.
  const std::vector<UnitEntry>& table = Table(d);
  if (table.empty()) return {"", 1.0};
  for (const UnitEntry& u : table) {
    if (unit == u.symbol) return {u.symbol, 1.0 / u.to_si};
  }
  return {table.front().symbol, 1.0};
}

ParsedQuantity ParseQuantity(std::string_view text, Dimension d) {
  ParsedQuantity out;
  text = Trim(text);
  // Split the longest numeric prefix from the unit.
  std::string_view number = text;
  std::string_view unit;
  if (const auto space = text.find_first_of(" \t"); space != std::string_view::npos) {
    number = text.substr(0, space);
    unit = Trim(text.substr(space));
  } else {
    // "2mm": the unit starts at the first letter that cannot continue a number (not e/E exponent).
    size_t i = 0;
    while (i < text.size()) {
      const char c = text[i];
      const bool numeric = (c >= '0' && c <= '9') || c == '.' || c == '-' || c == '+';
      const bool exponent =
          (c == 'e' || c == 'E') && i + 1 < text.size() &&
          ((text[i + 1] >= '0' && text[i + 1] <= '9') || text[i + 1] == '-' || text[i + 1] == '+');
      if (!numeric && !exponent) break;
      i += exponent ? 2 : 1;
    }
    number = text.substr(0, i);
    unit = text.substr(i);
  }
  const auto value = ParseNumber(number);
  if (!value) {
    out.error = "must be " + DimensionWithArticle(d) + " (a number" +
                (d == Dimension::kDimensionless ? "" : ", optionally with a unit") + ")";
    return out;
  }
  if (unit.empty()) {
    out.value_si = *value;
    return out;
  }
  for (const auto& u : Table(d)) {
    if (unit == u.symbol) {
      out.value_si = *value * u.to_si;
      out.unit = u.symbol;
      return out;
    }
  }
  out.error = "unknown unit '" + std::string(unit) + "' for " + DimensionWithArticle(d) +
              "; accepted: " + AcceptedUnits(d);
  return out;
}

}  // namespace gearnvh::config
