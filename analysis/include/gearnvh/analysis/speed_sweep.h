// The speed sweep behind `gearnvh sweep` (and the reports): Campbell data of the linearised tier
// and a waterfall of steady-state TE spectra, one exact run per speed, speeds in parallel.
#pragma once

#include <atomic>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/nvh/campbell.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

struct SpeedSweepOptions {
  long cycles = 512;            // recorded mesh cycles per speed; >= 2
  long transient_cycles = 200;  // unrecorded cycles first; >= 0
  long waterfall_cycles = 256;  // the last cycles of each run in the spectrum (<= cycles)
  double max_order = 0.0;       // waterfall up to this pinion order (0: 3.5 mesh orders)
  int threads = 0;              // 0: all hardware threads
  LadderMethod method = LadderMethod::kFused;
  // Cancellation (SolverOptions::cancel): once set, the runs in flight and the speeds not yet
  // started fail with the message "cancelled". Not owned; may be null.
  const std::atomic<bool>* cancel = nullptr;
};

struct SpeedPoint {
  double speed_rad_s = 0.0, speed_rpm = 0.0;
  bool ok = false;
  std::string message;  // why the run failed (ok = false) or a solver note
  // Results: NaN unless ok (a failed speed has none; 0 would read as a quiet speed).
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double te_rms = kNone, te_peak_to_peak = kNone;
  double events_per_cycle = kNone, drive_impacts_per_cycle = kNone, back_impacts_per_cycle = kNone;
  RattleRegime regime = RattleRegime::kNoImpact;  // of a point that is ok
  double matvec_per_cycle = 0.0, real_time_ratio = 0.0;
  std::vector<double> amplitude_m;  // waterfall row on the common order axis
};

struct SpeedSweepResult {
  std::vector<SpeedPoint> points;
  double order_step = 0.0;  // pinion orders per waterfall bin (z1 / waterfall_cycles)
  int order_bins = 0;
  AxisScale speed_scale = AxisScale::kLinear;  // of analysis.speed_sweep
  CampbellData campbell;
  int failed() const;  // speeds whose run failed (ok = false)
};

// (speeds done, total): called from worker threads, one call at a time (under a lock).
using SweepProgress = std::function<void(int, int)>;

// The memory RunSpeedSweep holds for the parts that grow with the cycles: every speed in flight
// (min(threads, speeds) at once) keeps its recording (PlanRecording) and its waterfall spectrum.
RunMemory SpeedSweepMemory(const SpeedSweepOptions& options, size_t speeds);

// Speeds whose `skip` entry is true are not run (ok = false, message "skipped"; MPI ranks fill
// them in); skip may be empty.
SpeedSweepResult RunSpeedSweep(const GearboxSpec& spec, const ComponentModel& model,
                               const ReducedModel& reduced, const SpeedSweepOptions& options,
                               const SweepProgress& progress = {},
                               const std::vector<bool>& skip = {});

}  // namespace gearnvh
