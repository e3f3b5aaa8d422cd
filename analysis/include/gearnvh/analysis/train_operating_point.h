// One operating point of a gear train (schema gearnvh/2) through the train solver
// (solver/train_stepper.h) and its per-mesh NVH: what `gearnvh simulate` prints for a train and
// what each point of a train's `sweep` holds.
//
// Per-mesh TE spectrum (docs/results.md, "Gear trains"): the amplitude-correct Hann spectrum
// (nvh/spectrum.h) of mesh i's TE at the recorder's uniform samples (dt = the fastest mesh period
// / samples_per_cycle) over the last W whole common periods of the record (every mesh and every
// engine order back in phase, so every periodic line of every mesh sits on a bin). W is the number
// of whole common periods in the record, bounded by the sample storage; 0 (no spectrum, a note
// says what is needed) when the record is shorter than one common period or the train has none.
// The lines are the pair's SidebandTable per mesh: its harmonics k fm_i, the shaft orders j f_s of
// every source and the sidebands k fm_i +- j f_s, listed only when they stand out of the local
// background and above the rounding floor. Sources: the input shaft (fin) with engine orders, and
// every body whose gears carry runout or pitch errors (f_<body>; fin for the input shaft); without
// any source only mesh harmonics are considered (the pair's rule).
#pragma once

#include <array>
#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/option_names.h"
#include "gearnvh/analysis/run_cost.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/reduction/tier_adequacy.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

struct TrainRunOptions {
  long cycles = 2000;                         // recorded cycles of the first mesh in the file, >= 1
  long transient = 500;                       // cycles of the first mesh before recording, >= 0
  int samples_per_cycle = 32;                 // per cycle of the fastest mesh, >= 4
  bool spectra = true;                        // keep the TE samples and compute per-mesh sidebands
  // Warn when the transient is shorter than three decay times of the slowest mode
  // (TransientDecayWarning: an eigensolve of the tier's generator; a sweep says it once itself).
  bool transient_warning = true;
  long max_spectrum_samples = long{1} << 21;  // TE samples kept per mesh for spectra, >= 1
  // Time histories (simulate --out and --uff): every mesh's TE, force and contact state at every
  // sample of the record (at most max_history_samples per mesh, as the pair's
  // SolverOptions::max_trajectory_samples), the record's contact events (at most
  // max_logged_events) and each mesh's TE spectrum (TrainOperatingPoint::histories, spectrum).
  bool histories = false;
  long max_history_samples = 4'000'000;  // >= 0
  long max_logged_events = 1'000'000;    // >= 0
  // A sweep's waterfall row: each mesh's TE amplitude spectrum (Hann) over the record's last
  // waterfall_samples samples (TrainOperatingPoint::waterfall); 0: none.
  long waterfall_samples = 0;                   // >= 0
  // From tier 2 on, every bearing's force on the housing (TrainOperatingPoint::bearing_forces):
  // its exact mean, RMS and extrema over the record; with `spectra` its lines at the meshes'
  // harmonics over the sideband window; with histories every sample of it.
  bool bearing_forces = false;
  EventMethod events = EventMethod::kSpectral;  // V3; V2 and V1 to validate
  Tier tier = Tier::kTier1;  // the train's tier (docs/gear-trains.md, "Tiers of a train")
  bool jumps = true;         // certified jumps of the transient (TrainStepperOptions::jumps)
  // Check the tier against the full FE model at this speed (reduction/tier_adequacy.h: the modes
  // the meshes see below 3x the highest mesh frequency) and warn when it misses one. A modal solve
  // of the full model: `simulate` asks for it, a sweep's speeds do not.
  bool tier_adequacy = false;
  // Polled by the table build and the stepper (per mesh, per grid segment): RunCancelled once
  // set. Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  // Called with each warning about the run's cost (SlowRunWarning) before the run starts, so a
  // command can say it on stderr at once; empty: not called (the warning is in `warnings` too).
  std::function<void(const std::string&)> before_run_warning;
  // Called with the memory estimate before the run starts (TrainOperatingPoint::memory): may add
  // the command's own parts, throw to refuse the run, or return a warning (kept in `warnings` and
  // passed to before_run_warning); empty: no check.
  std::function<std::string(RunMemory&)> before_run_memory;
  // A run whose cost estimate (EstimateRunCost) exceeds kSlowRunRefuseSeconds is refused unless
  // this is set; the refusal names names("allow-slow").
  bool allow_slow = false;
  OptionNames names;
  void Validate() const;
};

struct TrainMeshSidebands {
  long window_cycles = 0;  // cycles of this mesh in the spectrum window
  std::vector<SidebandRow> rows;
  AmplitudeSpectrum spectrum;  // of the window; kept with TrainRunOptions::histories only
};

// Every mesh's TE, force and contact state at the record's uniform samples, and its contact
// events (TrainRunOptions::histories).
struct TrainHistories {
  double start = 0.0, dt = 0.0;  // the first sample's time and the sample interval, s
  bool truncated = false;        // the record held more samples than max_history_samples
  std::vector<std::vector<double>> te, force;      // per mesh (file order), m and N
  std::vector<std::vector<ContactState>> contact;  // per mesh
  // With TrainRunOptions::bearing_forces, per bearing force row (TrainTables::bearing_force_rows:
  // 3 per bearing, x, y, z) its value at every kept sample, N.
  std::vector<std::vector<double>> bearing_force;
  // Per coupling (file order) its twist (rad) and torque (N m) at every kept sample, as
  // TrainCouplingResponse defines them.
  std::vector<std::vector<double>> coupling_twist, coupling_torque;
  std::vector<TrainEventRecord> events;            // in time order
  // The name of each contact an event's `mesh` indexes: the meshes (file order), then each
  // multi-stage coupling's stages after the first ("clutch stage 2").
  std::vector<std::string> contact_names;
  bool events_truncated = false;                   // more events than max_logged_events
};

// A bearing's force on the housing (TrainRunOptions::bearing_forces) in x, y and z, N: its mean
// (the static reaction and the mean of the motion), RMS about the mean and extrema, exact over the
// record (TrainOutputSummary); and its amplitude at each mesh's harmonics 1..3 over the sideband
// window's uniform samples (whole common periods, so each line sits on a bin of the
// Hann-windowed spectrum, read as is). Held error inputs (STE, runout, pitch errors) step the
// mesh force at every grid segment; the samples fold those steps' images into the lines.
struct TrainBearingForce {
  StructureBearing bearing;
  std::array<double, 3> mean{}, rms{}, min{}, max{};
  // With TrainRunOptions::histories, the window's spectra in x, y and z (empty without a window).
  std::array<AmplitudeSpectrum, 3> spectrum;
  struct Line {
    std::string label;  // "mesh g1-g2 1x"
    double frequency_hz = 0.0;
    std::array<double, 3> amplitude{};
  };
  std::vector<Line> lines;
};

// A coupling over the recorded window (exact, as the TE): its twist th_a - th_b in the shafts'
// direction of rotation (rad; the mean holds the static twist T / k) and its torque k twist + c
// twist' on the second shaft (N m).
struct TrainCouplingResponse {
  std::string name;
  TrainOutputSummary twist, torque;  // rad, N m (the torque of every stage, exact)
  // A multi-stage coupling's stages after the first: entries and time engaged (exact).
  std::vector<TrainCouplingStageStatistics> stages;
};

struct TrainOperatingPoint {
  Tier tier = Tier::kTier1;
  GearTrain train;
  TrainTables tables;
  TrainStepperOptions solver;
  TrainStepperSummary summary;
  TrainStatistics stats;
  std::vector<std::string> warnings;  // what the train solver does not model, said once
  // With TrainRunOptions::tier_adequacy: the options used (the frequency limit) and the verdict.
  std::optional<TierAdequacyOptions> adequacy_options;
  TierAdequacy adequacy;
  RunCostEstimate cost;  // estimated before the run
  double wall_s = 0.0;
  // The parts that grow with the recorded cycles, estimated before the run: the samples kept for
  // spectra and histories (TrainRecorder::KeepSeries), the events and the spectra.
  RunMemory memory;
  TrainHistories histories;  // empty unless TrainRunOptions::histories
  // Per mesh (file order) the TE spectrum of the record's tail (TrainRunOptions::
  // waterfall_samples); empty when none was asked for or the run stopped.
  std::vector<AmplitudeSpectrum> waterfall;
  // Spectra (empty `sidebands` when TrainRunOptions::spectra is false).
  long sideband_window_common_periods = 0;
  SidebandOptions sideband_options;
  std::vector<TrainMeshSidebands> sidebands;  // per mesh, file order
  std::vector<std::string> sideband_notes;
  // Per bearing (TrainTables::bearings order) with TrainRunOptions::bearing_forces at tier 2 or
  // higher; empty otherwise or when the run stopped.
  std::vector<TrainBearingForce> bearing_forces;
  std::vector<TrainCouplingResponse> couplings;  // per coupling, file order; empty if it stopped
  bool ok() const { return summary.info == TrainStepperSummary::Info::kSuccess; }
};

// Called about 100 times during the run with the simulated time reached (s) and the end time.
using TrainProgress = std::function<void(double time, double end)>;

TrainOperatingPoint RunTrainOperatingPoint(const TrainSpec& spec, const TrainRunOptions& options,
                                           const TrainProgress& progress = {});
// The same on the train of `spec` and its tables at options.tier, already built (BuildGearTrain,
// BuildTrainTablesAtTier): a command that estimated the run's cost on them runs them.
TrainOperatingPoint RunTrainOperatingPoint(const TrainSpec& spec, GearTrain train,
                                           TrainTables tables_at_tier,
                                           const TrainRunOptions& options,
                                           const TrainProgress& progress = {});

}  // namespace gearnvh
