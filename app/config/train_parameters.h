// The schema gearnvh/2 parameters that `atlas` axes and `orbits --sweep` vary on a gear train,
// named by their schema paths with the list index of the file:
//   operating.speed                      the input shaft's mean speed (rad/s)
//   operating.loads[i].torque            load i's torque (N m): the output load or a loose gear's
//                                        drag
//   operating.excitation[i].amplitude    engine order i's amplitude (rad/s^2)
//   meshes[i].backlash                   mesh i's backlash (m)
//   meshes[i].damping_ratio              mesh i's damping ratio
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::app {

// The dimension of a train parameter's values, nullopt when `name` is none of the forms above.
std::optional<config::Dimension> TrainParameterDimension(const std::string& name);

// Why `name` is not a train parameter (the accepted forms; for a schema-1 name, its train form).
std::string TrainParameterRejection(const std::string& name);

// "PARAMETER=FROM:TO:POINTS" for a train; InputError naming `field` (the option).
AtlasAxis ParseTrainAxisOption(const std::string& text, const std::string& field);

// Sets one parameter (SI). InputError naming `field` when the name is not a train parameter or its
// index is beyond the file's list (the message lists what the file has). The caller validates
// the variant (ValidateTrainSpec) before use.
void SetTrainParameter(TrainSpec& spec, const std::string& name, double value,
                       const std::string& field);

// How an axis value is shown: speed in rpm, torque in N m, backlash in µm, amplitude in rad/s².
struct TrainDisplayAxis {
  double scale = 1.0;  // display value = SI value * scale
  std::string unit;
};
TrainDisplayAxis TrainDisplayAxisFor(const std::string& name);

// ValidateTrainSpec on a variant; an InputError at one of the parameters `set` shows its value as
// the axis does (TrainDisplayAxisFor: "-10 µm"), not the SI number the variant holds.
void ValidateTrainVariant(const TrainSpec& variant, const std::vector<ParameterValue>& set);

}  // namespace gearnvh::app
