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

#include <algorithm>
#include <atomic>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "run_memory.h"

namespace gearnvh::app {

// How the caller names its options in messages: "--cycles" on the command line, "cycles" for
// the Python module's keyword (TrainOptionNames{""}).
struct TrainOptionNames {
  std::string prefix = "--";
  // A keyword spells a dashed option with underscores ("allow-slow" -> "allow_slow").
  std::string operator()(const std::string& option) const {
    std::string name = option;
    if (prefix.empty()) std::replace(name.begin(), name.end(), '-', '_');
    return prefix + name;
  }
};

struct TrainRunOptions {
  long cycles = 2000;                         // recorded cycles of the first mesh in the file, >= 1
  long transient = 500;                       // cycles of the first mesh before recording, >= 0
  int samples_per_cycle = 32;                 // per cycle of the fastest mesh, >= 4
  bool spectra = true;                        // keep the TE samples and compute per-mesh sidebands
  long max_spectrum_samples = long{1} << 21;  // TE samples kept per mesh for spectra, >= 1
  EventMethod events = EventMethod::kSpectral;  // V3; V2 and V1 to validate
  Tier tier = Tier::kTier1;  // the train's tier (docs/gear-trains.md, "Tiers of a train")
  bool jumps = true;         // certified jumps of the transient (TrainStepperOptions::jumps)
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
  TrainOptionNames names;
  void Validate() const;
};

// The run-cost estimate of a train run and what a command does with it (docs/cli.md, "Run
// cost"): the dense path takes about 2 rho sub-steps per simulated second, rho the solver's own
// bound on the spectral radius of the generator (BoundTupleRate, solver/train_rate_bound.h), each
// costing about kSubstepSecondsPerState2 m^2 (m the state dimension). Above kSlowRunWarnSeconds a
// warning, above kSlowRunRefuseSeconds a refusal unless the caller allows slow runs.
//
// The per-sub-step constant is a third of what was measured (65 us per sub-step at m = 86, i.e.
// ~9e-9 m^2 s: the manual-transmission example at tier 3 with a heavy rigid shaft, dense path, on
// the 2-core development machine, 2026-12-02) so that a faster machine is not refused a run that
// is not surely slow. The closed-form path (decomposed tuples), certified jumps and
// segment-run fusion can make the transient cheaper than the dense path; the recorded cycles are
// always stepped on sub-steps (the recorder's Taylor chunks).
constexpr double kSubstepSecondsPerState2 = 3e-9;
constexpr double kSlowRunWarnSeconds = 60.0;
constexpr double kSlowRunRefuseSeconds = 3600.0;

// The term of rho that dominates it (BoundTupleRate): the highest undamped mode sqrt(lambda_max(
// M^-1 K)), the symmetric damping lambda_max(M^-1 C), the gyroscopic (skew) part of a reduced
// tier's damping, or tooth friction.
enum class RateTerm { kStiffness, kDamping, kGyroscopic, kFriction };
const char* RateTermName(RateTerm term);

// What a run costs, estimated before it starts, on the tuple the run starts in with every mesh in
// drive contact (segment 0 of every mesh, t = 0): the solver's own bound rho on that tuple's
// spectral radius (tooth friction and a reduced tier's skew damping included), so the dense
// path's sub-step there is 1 / (2 rho) unless its second bound (the balanced row norm) is
// shorter; the highest frictionless undamped mode omega = sqrt(lambda_max(M^-1 K)) of that tuple
// and the body that moves most in it.
struct RunCostEstimate {
  double mode_hz = 0.0;          // the highest mode, Hz (frictionless)
  double fastest_mesh_hz = 0.0;  // the fastest mesh frequency, Hz
  int body = 0;                  // the body that moves most in the highest mode
  double substep_s = 0.0;        // 1 / (2 rho), s; 0 when rho is 0 or an eigenproblem failed
  double rho = 0.0;              // 1/s
  RateTerm dominant = RateTerm::kStiffness;
  double dominant_rate = 0.0;  // that term's part of rho, 1/s
  // The body the dominant term comes from: for kGyroscopic the body whose node has the largest
  // spin rate |w_b| I_p / I_d (the nutation a disk's gyroscopic moment drives), else `body`.
  int cause_body = 0;
  std::string cause_body_name;
  double cause_body_inertia = 0.0;  // its polar inertia, kg m^2
  double cause_nutation_rate = 0.0;  // kGyroscopic: |w_b| I_p / I_d at that node, rad/s
  Tier tier = Tier::kTier1;
  int state_dim = 0;        // m
  double simulated_s = 0.0;  // the simulated time the estimate is for, s (all runs)
  double substeps = 0.0;     // simulated_s / substep_s (all runs)
  double wall_s = 0.0;       // substeps * kSubstepSecondsPerState2 m^2 (/ parallel runs)
  int runs = 1;              // runs counted (a sweep's speeds, an atlas's cells, tiers)
};
// For `simulated_s` seconds of simulated time on `tables`. The structure is assembled for the
// gyroscopic cause's body when that term dominates (tiers 2+ only).
RunCostEstimate EstimateRunCost(const TrainTables& tables, double simulated_s = 0.0,
                                const TrainSpec* spec = nullptr);
// Several runs: sub-steps summed, wall time summed over `parallel` threads (>= 1), the cause that
// of the costliest run.
RunCostEstimate CombineRunCosts(const std::vector<RunCostEstimate>& runs, int parallel);

// The cost of running `what` ("the run", "the sweep's 12 speeds"): empty below
// kSlowRunWarnSeconds, else a warning naming the estimate and its cause. Above
// kSlowRunRefuseSeconds, unless `allow_slow`, throws InputError at names("allow-slow") (exit 2
// on the command line) stating the estimate, its cause and that the option allows the run.
std::string CheckRunCost(const RunCostEstimate& cost, bool allow_slow,
                         const std::string& what = "the run",
                         const TrainOptionNames& names = {});

// The warning text of a cost (whatever its size): the estimate and its cause.
std::string RunCostText(const RunCostEstimate& cost, const std::string& what);

struct TrainMeshSidebands {
  long window_cycles = 0;  // cycles of this mesh in the spectrum window
  std::vector<SidebandRow> rows;
};

struct TrainOperatingPoint {
  Tier tier = Tier::kTier1;
  GearTrain train;
  TrainTables tables;
  TrainStepperOptions solver;
  TrainStepperSummary summary;
  TrainStatistics stats;
  std::vector<std::string> warnings;  // what the train solver does not model, said once
  RunCostEstimate cost;               // estimated before the run
  double wall_s = 0.0;
  // The parts that grow with the recorded cycles, estimated before the run: the TE samples kept
  // for spectra (TrainRecorder::KeepTeSeries) and the spectrum of one mesh at a time.
  RunMemory memory;
  // Spectra (empty `sidebands` when TrainRunOptions::spectra is false).
  long sideband_window_common_periods = 0;
  SidebandOptions sideband_options;
  std::vector<TrainMeshSidebands> sidebands;  // per mesh, file order
  std::vector<std::string> sideband_notes;
  bool ok() const { return summary.info == TrainStepperSummary::Info::kSuccess; }
};

struct TrainCommandSettings {
  Tier tier = Tier::kTier1;
  EventMethod events = EventMethod::kSpectral;
};


// What `simulate` and `sweep` accept on a train: a tier the train has (`--tier` or
// analysis.tier; tiers 4, 5 and N20 need an elastic shaft) and no UFF file; the event method is
// EventMethodOf(method) (kFused means kV3: fusion is not built for trains).
// Throws InputError naming the option or key otherwise.
TrainCommandSettings CheckTrainCommandOptions(const std::optional<std::string>& tier_option,
                                              const TrainSpec& spec, LadderMethod method,
                                              const std::optional<std::string>& uff,
                                              const TrainOptionNames& names = {});

// `cycles` >= `min_cycles` and `transient` >= 0 (the counts a command runs), else InputError
// naming names("cycles") or names("transient").
void RequireCycleCounts(long cycles, long min_cycles, long transient,
                        const TrainOptionNames& names = {});

// The run-length limit of the file (GearboxLimits::kMaxSimulatedSeconds of simulated time) on the
// counts a command runs when --cycles or --transient overrides analysis: `cycles` + `transient`
// cycles of the first mesh at input speed `lowest_speed` (rad/s; a sweep's lowest) must last at
// most that long. InputError naming --transient when it was given, else --cycles; nothing to check
// when neither was given (ValidateTrainSpec has checked the file's counts).
void RequireRunLengthOfOptions(const TrainSpec& spec, double lowest_speed, long cycles,
                               long transient, const std::optional<long>& cycles_option,
                               const std::optional<long>& transient_option,
                               const TrainOptionNames& names = {});

// The lowest input speed a command runs at, rad/s: the operating speed, or the lower end of an
// axis (atlas --x/--y, orbits --sweep) that varies operating.speed. For RequireRunLengthOfOptions.
double LowestInputSpeed(const TrainSpec& spec, const std::optional<AtlasAxis>& x,
                        const std::optional<AtlasAxis>& y = std::nullopt);

// An axis a command runs (atlas --x/--y, orbits --sweep, given as `text`) that varies
// operating.speed, held at its fastest end to the pitch-line velocity limit of the fastest mesh
// (RequirePitchLineVelocity, in the unit the axis was written in): InputError naming `field`.
// `mesh` names that mesh for a pair ("the mesh"); "" names a train's ("meshes[1] (c-d)").
void RequireAxisWithinPitchLineLimit(const TrainSpec& spec, const AtlasAxis& axis,
                                     const std::string& text, const std::string& field,
                                     const std::string& mesh = "");

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

// `meshes` and `loose_gears` of `simulate --json` on a train (docs/cli.md), SI units.
nlohmann::json TrainMeshesJson(const TrainOperatingPoint& op);
nlohmann::json TrainLooseGearsJson(const std::vector<TrainLooseGearStatistics>& gears);
nlohmann::json TrainSidebandsJson(const std::vector<SidebandRow>& rows);

}  // namespace gearnvh::app
