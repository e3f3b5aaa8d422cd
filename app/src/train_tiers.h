// `gearnvh tiers` on a gear train (schema gearnvh/2): every tier the train has (tier 1, 2, 3 and,
// with an elastic shaft, 4, N40 full, N20 simple, N20 MTA) run through the train solver at the
// operating point, side by side: DOF, state dimension, per mesh TE RMS and per loose gear rattle
// index with their relative difference to the finest tier (most DOF), and cost (µs per cycle of
// the first mesh, real-time ratio, table cache bytes).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_spec.h"
#include "tiers_command.h"

namespace gearnvh::app {

struct TrainTierRow {
  std::string name;
  // A run that stopped keeps its DOF and state dimension; its results and cost are NaN (one per
  // mesh and loose gear still) and `message` says why.
  TrainStepperSummary::Info info = TrainStepperSummary::Info::kSuccess;
  std::string message;
  int dof = 0, state_dim = 0;
  std::vector<double> te_rms, te_rms_difference;              // per mesh: m, relative
  std::vector<double> rattle_index, rattle_index_difference;  // per loose gear: rad/s^2, relative
  double us_per_cycle = 0.0, real_time_ratio = 0.0;
  size_t table_bytes = 0;
  bool ok() const { return info == TrainStepperSummary::Info::kSuccess; }
};

struct TrainTiersComparison {
  std::vector<std::string> meshes, loose_gears;  // file order, body order
  std::vector<TrainTierRow> rows;
  size_t finest = 0;   // as TiersComparison::finest
  int failed = 0;      // rows whose run stopped
  nlohmann::json doc;  // `tiers --json` on a train without name and file
};

// Every tier the train has at the operating point, `run`'s cycles each (run.tier is ignored); a
// tier whose run stops is a failed row, and the others still run.
TrainTiersComparison CompareTrainTiers(const TrainSpec& spec, TrainRunOptions run,
                                       const TiersProgress& progress = {});

// What `tiers` runs on a train, from its options (the command line's or the Python module's,
// `names` saying how they are named in errors): --cycles (default min(analysis.cycles, 400)) and
// --transient (default min(analysis.transient_cycles, 200)) held to the run-length limit.
TrainRunOptions PlanTrainTiers(const TiersCommandOptions& options, const TrainSpec& spec,
                               const OptionNames& names = {});
// `tiers --json` on a train: the comparison's document with the train's name and `file`.
nlohmann::json TrainTiersDocument(const TrainTiersComparison& c, const TrainSpec& spec,
                                  const std::string& file);

// The `tiers` command on a loaded schema-2 file (text, JSON, --out tiers.json and tiers.csv).
int RunTrainTiers(const TiersCommandOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
