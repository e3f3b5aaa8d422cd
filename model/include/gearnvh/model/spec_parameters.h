// Schema parameters that analyses vary programmatically: atlas axes and orbit continuation, of a
// pair (GearboxSpec, schema gearnvh/1) and of a gear train (TrainSpec, schema gearnvh/2). Names
// are dotted schema paths; values are SI (the units of the specs).
#pragma once

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/train_spec.h"

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

// Sets one parameter through the train registry below (TrainOf, SetTrainParameter, GearboxOf;
// operating.torque is operating.loads[0].torque, mesh.backlash meshes[0].backlash, ...);
// ParameterNotVariable when it cannot. The caller re-validates the spec (ValidateGearboxSpec)
// before use.
void SetParameter(GearboxSpec& spec, const std::string& name, double value);

// A gear train's parameters, named by their schema paths with the list index of the file:
//   operating.speed                      the input shaft's mean speed (rad/s)
//   operating.loads[i].torque            load i's torque (N m): the output load or a loose gear's
//                                        drag
//   operating.loads[i].viscous           load i's viscous drag (N m s/rad)
//   operating.excitation[i].amplitude    engine order i's amplitude (rad/s^2; an acceleration
//                                        order's only: a torque order's is refused)
//   meshes[i].backlash                   mesh i's backlash (m)
//   meshes[i].damping_ratio              mesh i's damping ratio
//   meshes[i].friction_coefficient       mesh i's tooth friction coefficient
//   couplings.NAME.stiffness             coupling NAME's stiffness (N m/rad; multi-stage: the
//   first) couplings.NAME.damping               coupling NAME's damping (N m s/rad)
// A load a schema-1 file wrote on the pinion (TrainLoad::pinion_torque) varies as written.
enum class TrainParameter {
  kSpeed,
  kLoadTorque,
  kLoadViscous,
  kExcitationAmplitude,
  kBacklash,
  kDampingRatio,
  kFrictionCoefficient,
  kCouplingStiffness,
  kCouplingDamping
};
// Which of the forms above `name` is; nullopt when none.
std::optional<TrainParameter> TrainParameterOf(const std::string& name);
// Why `name` is not a train parameter (the accepted forms; for a schema-1 name, its train form).
std::string TrainParameterRejection(const std::string& name);
// Sets one parameter (SI). InputError naming `field` when the name is not a train parameter or its
// index is beyond the file's list (the message lists what the file has). The caller validates
// the variant (ValidateTrainSpec) before use.
void SetTrainParameter(TrainSpec& spec, const std::string& name, double value,
                       const std::string& field);

}  // namespace gearnvh
