// `gearnvh simulate` on a gear train (schema gearnvh/2): the train solver
// (solver/train_stepper.h), per-mesh and per-loose-gear results in text or JSON (docs/cli.md,
// docs/results.md "Gear trains").
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "gearnvh/model/train_spec.h"
#include "simulate_command.h"
#include "train_operating_point.h"

namespace gearnvh::app {

// The `simulate --json` document of a train run (without `lyapunov`), SI units; `file` is what
// the document names as its source.
nlohmann::json TrainSimulationJson(const TrainOperatingPoint& op, const TrainSpec& spec,
                                   const std::string& file, Tier tier);

// Runs the train and prints; returns the exit code. InputError for options trains do not support
// yet (a tier other than 1, --method v1/v2, --uff).
int SimulateTrain(const SimulateOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
