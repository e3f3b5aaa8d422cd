// `gearnvh simulate` on a gear train (schema gearnvh/2): the tier-1 train solver
// (solver/train_stepper.h), per-mesh and per-loose-gear results in text or JSON (docs/cli.md,
// docs/results.md "Gear trains").
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "gearnvh/model/train_spec.h"
#include "simulate_command.h"

namespace gearnvh::app {

// Runs the train and prints; returns the exit code. InputError for options trains do not support
// yet (a tier other than 1, --method v1/v2, --uff).
int SimulateTrain(const SimulateOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
