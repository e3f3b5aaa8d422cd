// Chaos atlas: a 2-D grid over two schema parameters (docs/design.md §5). Each cell is one gearbox
// variant taken through model -> reduction -> tables -> settled exact run with a tangent vector:
//   largest Lyapunov exponent (1/s and per forcing cycle, with its standard error),
//   impacts per mesh cycle on each flank, rattle index, separation fraction, regime.
// Rattle index: the impact energy per forcing (rattle) cycle, sum of (1/2) m_e g'^2 over impacts
// per forcing period, J — the energy the flanks take per firing pulse. (The acceleration ratio
// needs a second, backlash-free run per cell and is left to `simulate`.)
// Regime: kNoImpact | kSingleSided | kDoubleSided from the impacts (rattle.h), replaced by
// kChaotic when lambda T_f > chaos_threshold and lambda exceeds three standard errors.
// Cells are independent and deterministic: they run in parallel (OpenMP, dynamic schedule) and
// give bitwise the same numbers for any thread count.
#pragma once

#include <atomic>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

struct AtlasOptions {
  Tier tier = Tier::kTier1;
  long transient_cycles = 300;                  // mesh cycles settled before measuring; >= 0
  long cycles = 1080;                           // mesh cycles averaged per cell; >= 8
  int threads = 0;                              // 0: all hardware threads
  double chaos_threshold = 0.01;                // lambda T_f above which a cell is chaotic; > 0
  EventMethod events = EventMethod::kSpectral;  // V3; V2 and V1 to validate
  // Cancellation (SolverOptions::cancel): once set, cells in flight and cells not yet started
  // fail with the message "cancelled". Not owned; may be null.
  const std::atomic<bool>* cancel = nullptr;
  // How an input error of a cell is worded, given the parameters the cell's variant was set to:
  // the library's message names its own fields ("tier") and SI values; the app words it at the
  // path or keyword the user set, with the axis's value in the unit it is shown in. Empty: what().
  std::function<std::string(const InputError&, const std::vector<ParameterValue>&)>
      input_error_message;
  void Validate() const;  // throws InputError naming the field
};

struct AtlasCell {
  int ix = 0, iy = 0;
  double x = 0.0, y = 0.0;  // parameter values, SI
  bool ok = false;
  std::string message;  // why the cell failed
  // Results: NaN unless ok (a failed cell has none; 0 would read as a quiet cell).
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double lyapunov_per_s = kNone, lyapunov_per_forcing_cycle = kNone;
  double lyapunov_standard_error = kNone;
  double drive_impacts_per_cycle = kNone, back_impacts_per_cycle = kNone;  // per mesh cycle
  double rattle_index = kNone;                                             // J per forcing cycle
  double impact_velocity_rms = kNone;                                      // m/s
  double separation_fraction = kNone;
  RattleRegime regime = RattleRegime::kNoImpact;  // of a cell that is ok
  double wall_s = 0.0;
};

// Where a failed cell's reason goes (each atlas cell type has one: generic code sets it).
inline std::string& FailureMessage(AtlasCell& cell) { return cell.message; }

struct AtlasResult {
  AtlasAxis x, y;
  std::vector<AtlasCell> cells;  // row-major: index iy * x.points + ix
  int threads = 1;
  double wall_s = 0.0;
  int Failed() const;
};

// The value of point i of an axis (SweepRange::Point: even or geometric from `from` to `to`).
double AxisValue(const AtlasAxis& axis, int i);

// One cell; never throws (a failure is reported in the cell).
AtlasCell ComputeAtlasCell(const GearboxSpec& base, const AtlasAxis& x, const AtlasAxis& y, int ix,
                           int iy, const AtlasOptions& options);

// (cells done, total): called under a lock, from worker threads.
using AtlasProgress = std::function<void(int, int)>;
// Called under the same lock with every cell as soon as it is computed (checkpoints).
using AtlasCellCallback = std::function<void(const AtlasCell&)>;

// Every cell of the grid whose `skip` entry is false (skip may be empty: all cells). Skipped cells
// are returned with ok = false and message "skipped" (the caller fills them, e.g. on resume).
AtlasResult RunChaosAtlas(const GearboxSpec& base, const AtlasAxis& x, const AtlasAxis& y,
                          const AtlasOptions& options, const AtlasProgress& progress = {},
                          const std::vector<bool>& skip = {},
                          const AtlasCellCallback& on_cell = {});

}  // namespace gearnvh
