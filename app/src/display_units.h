// How quantities are shown to the user: speed and torque in the units the gearbox file used
// (rpm, N m, ...) and lengths of the TE in µm; plural-aware counts (Count) come with it.
#pragma once

#include <functional>
#include <string>

#include "gearnvh/analysis/written_numbers.h"
#include "gearnvh/model/count_text.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::app {

// "800 rpm", "0.5 N m", "12000 rpm": the SI value in `unit`, 4 significant digits (Significant).
std::string Format(double value_si, const DisplayUnit& unit);

// `v` as an engineer writes it, with `digits` significant digits but without an exponent between
// 1e-4 and 1e15 (digits of the integer part are never dropped): "12000", "12346", "0.5", "700.5".
// Outside that range, or not finite, as printf's %g.
std::string Significant(double v, int digits = 4);

// The operating torque as given: "0.5 N m on the wheel", "20 N m on the pinion".
std::string TorqueText(const GearboxSpec& spec);

// A train's loads as given: "20 N m on layshaft, 0.05 N m on g4" ("none" without loads).
std::string TrainLoadsText(const TrainSpec& spec);

// How a schema parameter (an atlas or orbit-sweep axis) is shown: its label with the unit, the
// factor from SI, the unit alone. Speed and torque use the units the gearbox file used.
struct DisplayAxis {
  std::string label;
  double scale = 1.0;
  std::string unit;
};
DisplayAxis DisplayAxisFor(const std::string& parameter, const GearboxSpec& spec);

// A pair's axis value as the axis shows it ("-10 µm", "600 rpm"), for the messages of failed
// atlas cells and orbit points (UserWording). Keeps a copy of `spec`'s units.
std::function<std::string(const ParameterValue&)> PairAxisValueText(const GearboxSpec& spec);

}  // namespace gearnvh::app
