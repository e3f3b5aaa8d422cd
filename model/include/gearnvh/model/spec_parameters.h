// Schema parameters that analyses vary programmatically: atlas axes and orbit continuation.
// Names are dotted schema paths; values are SI (the units of GearboxSpec).
#pragma once

#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

// operating.speed (rad/s), operating.torque (N m), mesh.backlash (m), mesh.damping_ratio,
// mesh.friction_coefficient, operating.excitation[0].amplitude (rad/s^2).
const std::vector<std::string>& VariableParameters();

// Sets one parameter. Throws InputError naming `field` (the option or YAML path that asked for it)
// when the name is unknown or the spec has no such entry (no excitation order to change). The
// caller re-validates the spec (ValidateGearboxSpec) before use.
void SetParameter(GearboxSpec& spec, const std::string& name, double value,
                  const std::string& field);
double GetParameter(const GearboxSpec& spec, const std::string& name, const std::string& field);

}  // namespace gearnvh
