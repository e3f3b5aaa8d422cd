// `gearnvh orbits` on a gear train (schema gearnvh/2): period-M orbits (M common periods of the
// train) by Newton shooting on the exact train flow (nvh/train_orbit_scan.h), at the file's
// operating point or along one train parameter (`--sweep`, config/train_parameters.h); Floquet
// multipliers on the quotient by the free rotation, stability, text and JSON (docs/cli.md).
#pragma once

#include "gearnvh/model/train_spec.h"
#include "orbits_command.h"

namespace gearnvh::app {

int OrbitsTrain(const OrbitsCommandOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
