#include "display_units.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "config/gearbox_loader.h"

namespace gearnvh::app {

std::string Format(double value_si, const DisplayUnit& unit) {
  return Significant(value_si * unit.per_si) + " " + unit.symbol;
}

std::string Significant(double v, int digits) {
  const double magnitude = std::abs(v);
  if (v == 0.0) return "0";
  if (!std::isfinite(v) || magnitude < 1e-4 || magnitude >= 1e15) {
    return fmt::format("{:.{}g}", v, digits);
  }
  // %g's digits, rounded first so that 9.99996 at 4 digits counts as 10 (one digit before the
  // point), and fixed: the decimals left after the integer part.
  const double rounded = std::stod(fmt::format("{:.{}e}", v, digits - 1));
  const int before = static_cast<int>(std::floor(std::log10(std::abs(rounded)))) + 1;
  std::string s = fmt::format("{:.{}f}", v, std::max(0, digits - before));
  if (s.find('.') != std::string::npos) {
    s.erase(s.find_last_not_of('0') + 1);
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

std::string TrainLoadsText(const TrainSpec& spec) {
  std::string text;
  for (const TrainLoad& load : spec.operating.loads) {
    if (!text.empty()) text += ", ";
    if (load.torque > 0.0 || load.viscous == 0.0) text += Format(load.torque, load.torque_unit);
    if (load.viscous > 0.0) {
      text += std::string(load.torque > 0.0 ? " and " : "") + "viscous " +
              Format(load.viscous, load.viscous_unit);
    }
    text += " on " + load.on;
    if (!load.relative_to.empty()) text += " relative to " + load.relative_to;
  }
  return text.empty() ? "none" : text;
}

std::string TorqueText(const GearboxSpec& spec) {
  return Format(spec.operating.torque, spec.operating.torque_unit) + " on the " +
         TorqueOnName(spec.operating.torque_on);
}

DisplayAxis DisplayAxisFor(const std::string& parameter, const GearboxSpec& spec) {
  const OperatingSpec& op = spec.operating;
  if (parameter == "operating.speed") {
    return {"pinion speed (" + op.speed_unit.symbol + ")", op.speed_unit.per_si,
            op.speed_unit.symbol};
  }
  if (parameter == "operating.torque") {
    return {std::string("torque on the ") + TorqueOnName(op.torque_on) + " (" +
                op.torque_unit.symbol + ")",
            op.torque_unit.per_si, op.torque_unit.symbol};
  }
  if (parameter == "mesh.backlash") return {"backlash (µm)", 1e6, "µm"};
  if (parameter == "mesh.damping_ratio") return {"mesh damping ratio (-)", 1.0, ""};
  if (parameter == "mesh.friction_coefficient") return {"friction coefficient (-)", 1.0, ""};
  if (parameter == "operating.excitation[0].amplitude") {
    return {"excitation amplitude (rad/s²)", 1.0, "rad/s²"};
  }
  return {parameter + " (SI)", 1.0, ""};
}

std::function<std::string(const ParameterValue&)> PairAxisValueText(const GearboxSpec& spec) {
  GearboxSpec units;  // only the units DisplayAxisFor reads
  units.operating.speed_unit = spec.operating.speed_unit;
  units.operating.torque_unit = spec.operating.torque_unit;
  units.operating.torque_on = spec.operating.torque_on;
  return [units](const ParameterValue& p) {
    const DisplayAxis d = DisplayAxisFor(p.name, units);
    return config::AxisValueText(p.value * d.scale, d.unit);
  };
}

}  // namespace gearnvh::app
