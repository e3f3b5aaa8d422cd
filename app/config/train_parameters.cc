#include "train_parameters.h"

#include <numbers>

#include "gearnvh/model/input_error.h"

namespace gearnvh::app {

using config::Dimension;

std::optional<Dimension> TrainParameterDimension(const std::string& name) {
  const std::optional<TrainParameter> p = TrainParameterOf(name);
  if (!p) return std::nullopt;
  switch (*p) {
    case TrainParameter::kSpeed:
      return Dimension::kAngularSpeed;
    case TrainParameter::kLoadTorque:
      return Dimension::kTorque;
    case TrainParameter::kLoadViscous:
      return Dimension::kRotationalDamping;
    case TrainParameter::kExcitationAmplitude:
      return Dimension::kAngularAcceleration;
    case TrainParameter::kBacklash:
      return Dimension::kLength;
    case TrainParameter::kDampingRatio:
    case TrainParameter::kFrictionCoefficient:
      return Dimension::kDimensionless;
    case TrainParameter::kCouplingStiffness:
      return Dimension::kRotationalStiffness;
    case TrainParameter::kCouplingDamping:
      return Dimension::kRotationalDamping;
  }
  return std::nullopt;
}

AtlasAxis ParseTrainAxisOption(const std::string& text, const std::string& field) {
  return config::ParseAxisOption(text, field, TrainParameterDimension, TrainParameterRejection);
}

TrainDisplayAxis TrainDisplayAxisFor(const std::string& name) {
  const std::optional<TrainParameter> p = TrainParameterOf(name);
  if (!p) return {};
  switch (*p) {
    case TrainParameter::kSpeed:
      return {60.0 / (2.0 * std::numbers::pi), "rpm"};
    case TrainParameter::kLoadTorque:
      return {1.0, "N m"};
    case TrainParameter::kLoadViscous:
      return {1.0, "N m s/rad"};
    case TrainParameter::kExcitationAmplitude:
      return {1.0, "rad/s²"};
    case TrainParameter::kBacklash:
      return {1e6, "µm"};
    case TrainParameter::kDampingRatio:
    case TrainParameter::kFrictionCoefficient:
      return {};
    case TrainParameter::kCouplingStiffness:
      return {1.0, "N m/rad"};
    case TrainParameter::kCouplingDamping:
      return {1.0, "N m s/rad"};
  }
  return {};
}

std::string TrainAxisValueText(const ParameterValue& p) {
  const TrainDisplayAxis d = TrainDisplayAxisFor(p.name);
  return config::AxisValueText(p.value * d.scale, d.unit);
}

void ValidateTrainVariant(const TrainSpec& variant, const std::vector<ParameterValue>& set) {
  try {
    ValidateTrainSpec(variant);
  } catch (const InputError& e) {
    throw config::AtParameterValue(e, set, TrainAxisValueText);
  }
}

}  // namespace gearnvh::app
