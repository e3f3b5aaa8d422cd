// The speed sweep of a gear train (schema gearnvh/2) behind `gearnvh sweep` and the train report:
// one train run per input speed of analysis.speed_sweep (RunTrainOperatingPoint), speeds in
// parallel, and per speed each mesh's TE, mesh force and rattle and each loose gear's rattle index
// (docs/cli.md, "`sweep` on a gear train").
#pragma once

#include <algorithm>
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/train_statistics.h"

namespace gearnvh {

struct TrainSweepOptions {
  long cycles = 512;     // recorded cycles of the first mesh per speed, >= 1
  long transient = 200;  // cycles of the first mesh before recording, >= 0
  // The waterfall: each mesh's TE spectrum over the last WaterfallCycles() = min(waterfall_cycles,
  // cycles) cycles of the fastest mesh (waterfall_cycles >= 1), up to max_order input-shaft
  // orders (0: 3.5 times the fastest mesh's order).
  long waterfall_cycles = 256;
  double max_order = 0.0;
  long WaterfallCycles() const { return std::min(waterfall_cycles, cycles); }
  int threads = 0;                              // 0: all hardware threads
  EventMethod events = EventMethod::kSpectral;  // V3; V2 and V1 to validate
  Tier tier = Tier::kTier1;                     // the train's tier (TrainRunOptions::tier)
  // Passed to every speed's run (TrainRunOptions::cancel); a cancelled speed fails with its
  // message. Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  // The sweep's run-cost estimate (EstimateTrainSweepCost) is checked before any speed runs
  // (CheckRunCost): refused above an hour unless allow_slow, names("allow-slow") in the message;
  // a warning above a minute goes to before_run_warning (when set).
  bool allow_slow = false;
  OptionNames names;
  // The speeds are shared round robin among this many processes (MPI ranks), each running its
  // share (RunTrainSweep's skip): the cost check counts one share, ceil(points / ranks) speeds,
  // the same on every process. >= 1.
  int ranks = 1;
  std::function<void(const std::string&)> before_run_warning;
  void Validate() const;
};

struct TrainSweepPoint {
  double speed_rad_s = 0.0, speed_rpm = 0.0;
  bool ok = false;
  std::string message;  // why the run failed
  double real_time_ratio = 0.0;
  double recorded_s = 0.0;
  std::vector<double> mesh_periods;                   // s, per mesh
  std::vector<TrainMeshStatistics> meshes;            // file order
  std::vector<TrainLooseGearStatistics> loose_gears;  // body order (rank at this speed inside)
  std::vector<TrainCouplingResponse> couplings;       // file order; empty when the run failed
  // Per mesh the waterfall row: TE amplitude (m) at orders b * order_step of the input shaft,
  // b < order_bins (TrainSweepResult); empty when the run failed.
  std::vector<std::vector<double>> waterfall;
  // Impacts (drive + back) per cycle of mesh i: the mesh's rattle index.
  double ImpactsPerCycle(size_t mesh) const;
};

struct TrainSweepResult {
  std::vector<std::string> mesh_names, loose_gear_names;
  std::vector<TrainSweepPoint> points;  // ascending input speed
  // The waterfall's order axis, in orders of the input shaft: bin b at b * order_step (the fastest
  // mesh's order / waterfall_cycles), b < order_bins; each mesh's fundamental (its mesh order).
  double order_step = 0.0;
  int order_bins = 0;
  std::vector<double> mesh_orders;
  AxisScale speed_scale = AxisScale::kLinear;  // of analysis.speed_sweep
  int failed() const;
};

// The cost of the sweep's runs on one process (options.ranks): each speed's transient and cycles
// at the smaller of the estimates at the sweep's two end speeds (the cost per run varies
// monotonically with the speed, so no speed costs less), over the threads.
RunCostEstimate EstimateTrainSweepCost(const TrainSpec& spec, const TrainSweepOptions& options);

// Each mesh's order of the input shaft, file order: its mesh frequency over the input shaft's
// rotation frequency (z_a |w_a| / |w_in|).
std::vector<double> MeshOrders(const TrainSpec& spec);

using TrainSweepProgress = std::function<void(int done, int total)>;

// Runs every speed of spec.analysis.speed_sweep (the input shaft's speed); a speed whose run
// throws or stops is kept with ok = false and its message, the others go on. Speeds whose `skip`
// entry is true are not run (ok = false, message "skipped": MPI ranks fill them in); skip may be
// empty.
TrainSweepResult RunTrainSweep(const TrainSpec& spec, const TrainSweepOptions& options,
                               const TrainSweepProgress& progress = {},
                               const std::vector<bool>& skip = {});

// The result's loose_gear_names from its first successful speed (body order); RunTrainSweep calls
// it, and a caller that fills in skipped speeds calls it again.
void NameLooseGears(TrainSweepResult& result);

}  // namespace gearnvh
