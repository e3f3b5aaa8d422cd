#include "gearnvh/model/spec_parameters.h"

#include "gearnvh/model/input_error.h"

namespace gearnvh {

const std::vector<std::string>& VariableParameters() {
  static const std::vector<std::string> names{
      "operating.speed",    "operating.torque",          "mesh.backlash",
      "mesh.damping_ratio", "mesh.friction_coefficient", "operating.excitation[0].amplitude"};
  return names;
}

namespace {

double* Slot(GearboxSpec& spec, const std::string& name, const std::string& field) {
  if (name == "operating.speed") return &spec.operating.speed;
  if (name == "operating.torque") return &spec.operating.torque;
  if (name == "mesh.backlash") return &spec.mesh.backlash;
  if (name == "mesh.damping_ratio") return &spec.mesh.damping_ratio;
  if (name == "mesh.friction_coefficient") return &spec.mesh.friction_coefficient;
  if (name == "operating.excitation[0].amplitude") {
    if (spec.operating.excitation.empty()) {
      throw InputError(field, 0, name, "the gearbox has no operating.excitation order to vary");
    }
    return &spec.operating.excitation[0].amplitude;
  }
  std::string known;
  for (const std::string& n : VariableParameters()) known += (known.empty() ? "" : ", ") + n;
  throw InputError(field, 0, name, "must be one of " + known);
}

}  // namespace

void SetParameter(GearboxSpec& spec, const std::string& name, double value,
                  const std::string& field) {
  *Slot(spec, name, field) = value;
}

double GetParameter(const GearboxSpec& spec, const std::string& name, const std::string& field) {
  GearboxSpec copy = spec;  // Slot needs a mutable spec; parameters are few and specs small
  return *Slot(copy, name, field);
}

}  // namespace gearnvh
