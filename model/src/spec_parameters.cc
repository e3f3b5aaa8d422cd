#include "gearnvh/model/spec_parameters.h"

namespace gearnvh {

const std::vector<std::string>& VariableParameters() {
  static const std::vector<std::string> names{
      "operating.speed",    "operating.torque",          "mesh.backlash",
      "mesh.damping_ratio", "mesh.friction_coefficient", "operating.excitation[0].amplitude"};
  return names;
}

void SetParameter(GearboxSpec& spec, const std::string& name, double value) {
  double* slot = nullptr;
  if (name == "operating.speed") slot = &spec.operating.speed;
  if (name == "operating.torque") slot = &spec.operating.torque;
  if (name == "mesh.backlash") slot = &spec.mesh.backlash;
  if (name == "mesh.damping_ratio") slot = &spec.mesh.damping_ratio;
  if (name == "mesh.friction_coefficient") slot = &spec.mesh.friction_coefficient;
  if (name == "operating.excitation[0].amplitude") {
    if (spec.operating.excitation.empty()) {
      throw ParameterNotVariable(name, "the gearbox has no operating.excitation order to vary");
    }
    slot = &spec.operating.excitation[0].amplitude;
  }
  if (slot == nullptr) {
    std::string known;
    for (const std::string& n : VariableParameters()) known += (known.empty() ? "" : ", ") + n;
    throw ParameterNotVariable(name, "must be one of " + known);
  }
  *slot = value;
}

}  // namespace gearnvh
