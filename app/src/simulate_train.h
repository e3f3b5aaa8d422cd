// `gearnvh simulate` on a gear train (schema gearnvh/2): the train solver
// (solver/train_stepper.h), per-mesh and per-loose-gear results in text or JSON (docs/cli.md,
// docs/results.md "Gear trains").
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/train_lyapunov.h"
#include "simulate_command.h"

namespace gearnvh::app {

// The `simulate --json` document of a train run (without `lyapunov`), SI units; `file` is what
// the document names as its source.
nlohmann::json TrainSimulationJson(const TrainOperatingPoint& op, const TrainSpec& spec,
                                   const std::string& file, Tier tier);

// What `simulate` runs on a train, from its options (the command line's or the Python module's,
// `names` saying how they are named in errors): the run (cycles, transient, 32 samples per cycle,
// tier, event method) and the Lyapunov exponents asked for. Throws InputError for a tier the
// train lacks, --uff, --cycles < 1 (< 8 with --lyapunov), --transient < 0, a run beyond the
// run-length limit and --lyapunov outside 1 .. 2n - 2 (less 2 per fixed shaft).
struct TrainSimulatePlan {
  TrainRunOptions run;
  std::optional<int> lyapunov;
};
TrainSimulatePlan PlanTrainSimulate(const SimulateOptions& options, const TrainSpec& spec,
                                    const OptionNames& names = {});

// `simulate --lyapunov K`: the K largest exponents over the run's transient and cycles, a second
// run from the static state of `op`'s tables. progress(fraction done); run.cancel is passed on.
TrainLyapunovSummary RunTrainLyapunov(const TrainOperatingPoint& op, const TrainRunOptions& run,
                                      int exponents,
                                      const std::function<void(double)>& progress = {});
// `lyapunov` of `simulate --json` (docs/cli.md).
nlohmann::json TrainLyapunovJson(const TrainLyapunovSummary& l);

// Runs the train and prints; returns the exit code. InputError for options trains do not support
// yet (a tier other than 1, --method v1/v2, --uff).
int SimulateTrain(const SimulateOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
