// The units and display of the schema gearnvh/2 parameters that `atlas` axes and `orbits --sweep`
// vary on a gear train (the registry itself: TrainParameterOf and SetTrainParameter,
// gearnvh/model/spec_parameters.h).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::app {

// The dimension of a train parameter's values, nullopt when `name` is none (TrainParameterOf).
std::optional<config::Dimension> TrainParameterDimension(const std::string& name);

// "PARAMETER=FROM:TO:POINTS" for a train; InputError naming `field` (the option).
AtlasAxis ParseTrainAxisOption(const std::string& text, const std::string& field);

// How an axis value is shown: speed in rpm, torque in N m, backlash in µm, amplitude in rad/s².
struct TrainDisplayAxis {
  double scale = 1.0;  // display value = SI value * scale
  std::string unit;
};
TrainDisplayAxis TrainDisplayAxisFor(const std::string& name);

// A parameter's value as its axis shows it (TrainDisplayAxisFor): "-10 µm".
std::string TrainAxisValueText(const ParameterValue& p);

// ValidateTrainSpec on a variant; an InputError at one of the parameters `set` shows its value as
// the axis does (TrainDisplayAxisFor: "-10 µm"), not the SI number the variant holds.
void ValidateTrainVariant(const TrainSpec& variant, const std::vector<ParameterValue>& set);

}  // namespace gearnvh::app
