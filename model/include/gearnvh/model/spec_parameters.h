// Schema parameters that analyses vary programmatically: atlas axes and orbit continuation.
// Names are dotted schema paths; values are SI (the units of GearboxSpec).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

// operating.speed (rad/s), operating.torque (N m), mesh.backlash (m), mesh.damping_ratio,
// mesh.friction_coefficient, operating.excitation[0].amplitude (rad/s^2).
const std::vector<std::string>& VariableParameters();

// A parameter SetParameter cannot set: not one of VariableParameters(), or one the spec has no
// entry for (no excitation order to change). The caller knows where the name came from (a YAML
// path or a command-line option) and checks it first (the app restates `reason()` there), so
// reaching this during an analysis is a bug of the caller.
class ParameterNotVariable : public std::invalid_argument {
 public:
  ParameterNotVariable(const std::string& name, const std::string& reason)
      : std::invalid_argument(name + ": " + reason), reason_(reason) {}
  const std::string& reason() const { return reason_; }

 private:
  std::string reason_;
};

// A parameter a variant was given: its name and its value (SI).
struct ParameterValue {
  std::string name;
  double value = 0.0;
};

// Sets one parameter; ParameterNotVariable when it cannot. The caller re-validates the spec
// (ValidateGearboxSpec) before use.
void SetParameter(GearboxSpec& spec, const std::string& name, double value);

}  // namespace gearnvh
