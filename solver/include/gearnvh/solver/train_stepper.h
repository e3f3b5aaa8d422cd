// Exact event-driven propagation of a gear train at tier 1 (docs/design.md §11, §4.4).
//
// Grid: TrainGrid walks the union of every mesh's segment boundaries (train_tables.h). Per grid
// segment of length h the engine orders' states are set to their values at its start (then carried
// exactly by the generator's exosystem) and the error inputs to their means over it, and
// the tuple (segment index, contact state) of every mesh fixes the generator (TrainSystemCache).
// Per tuple with a usable decomposition (V3): w = S^-1 z, and every relevant wall of every mesh has
// its closed-form gap (ClosedFormGap::FirstRise):
//   drive: g+_i falling through 0 -> free;   back: g-_i rising through 0 -> free;
//   free:  g+_i rising through 0 -> drive,   g-_i falling through 0 -> back.
// The earliest root over all gaps is the event; the state is propagated there exactly
// (z = S e^{D t*} w). Roots within kSimultaneous * h + 4 eps t of the earliest are simultaneous:
// their meshes switch together, in the order of their roots. A root with |g'| below
// grazing_rate_tolerance whose gap curves back inside is a grazing touch: counted, the state is
// kept, the search resumes 1e-12 h past it (as the pair). A state found outside a wall at the
// start of a grid segment (the unloaded error e_ij jumps at boundaries) by more than the wall
// tolerance 1e-12 b_i + 64 eps sum |c z| switches at once.
// Dense path (a tuple not decomposed yet, TrainTableOptions::decompose_after_visits, or whose
// decomposition is ill-conditioned): sub-steps with rho(A) D <= 1/2 and ||S A S^-1|| D <= 1.5 (as
// TrainSystem::substep says) on the Taylor polynomial of the state (20 terms: the remainder is
// below e^1.5 1.5^21 / 21! ||S z|| < 4.4e-16 ||S z||); each gap of a sub-step is a scalar
// polynomial; a wall it cannot reach (|g(0)| against sum_{p>=1} |g_p| D^p plus ||v||_1 times the
// remainder) is skipped, else its first crossing is the pair's V2 polynomial search (taylor_root.h:
// samples plus every interior maximum between them, so a brief excursion is not missed), with the
// same grazing rule as V3. Never silently wrong: a tuple either decomposes within the condition
// limit or takes this path. Event methods (TrainStepperOptions::events), as the pair's locators
// (event_locator.h):
//   V3 (kSpectral, default): the closed form above, the dense path for the other tuples.
//   V2 (kTaylor): every tuple on the dense path.
//   V1 (kDyadic, the baseline): sub-steps of length d <= D, one dense propagator expm(A d) each,
//     screened as the pair's V1 (end point outside, or the gap turned back towards the wall); a
//     flagged sub-step is walked on dyadic propagators expm(A d 2^-l), l = 1..34, built for it, and
//     the event placed at the end of the cell holding the crossing (times quantised to d 2^-34).
//     Tables are built per sub-step (a train's grid segments have many lengths): slow, and only
//     for validation.
// Free rotation: r (th_j ~ |w_j|) changes no gap and no force in any tuple, so its position drift
// is removed (x <- x - r r~ x) once per common period (once per input revolution without one).
// Certified jumps (TrainStepperOptions::jumps, V3 only, never with a tangent attached): at a
// common period's start in the unrecorded transient, when every mesh is in contact and none has
// switched (or grazed) since the previous period start, the cycle map of that contact combination
// over the common period (train_cycle_map.h; built once, only when the period has at most
// max_cycle_map_segments grid segments) certifies that contact holds forever, and the state jumps
// K whole periods, as far as the recording start allows (the pair's rule: jumped periods record
// nothing). The certificate is retried at each following period start while it fails.
// Segment-run fusion (TrainStepperOptions::fusion_levels, V3 only, never with a tangent attached,
// only on unrecorded time): at a grid segment start at position p of the common period, the
// longest certified aligned run of 2..2^L grid segments in the current contact combination is
// applied as one affine map (train_segment_runs.h); refused runs are stepped.
// Once the cache holds the visited tuples (and has decomposed those due), Run() allocates nothing;
// nor does a certificate or a jump once the cycle map is built, nor a fused run once its tables
// are held.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/train_cycle_map.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

class TrainRecorder;
class TrainSegmentRuns;
class TrainTangentPropagator;

// The union grid of the meshes' segment boundaries, from integer cycle counts.
class TrainGrid {
 public:
  explicit TrainGrid(const TrainTables& tables);
  double start() const { return start_; }
  double end() const { return end_; }
  const std::vector<int>& segments() const { return segment_; }
  const std::vector<long>& cycles() const { return cycle_; }  // whole cycles of each mesh done
  void Next();                                                // the following grid segment
  // From the start of a common period (every mesh at segment 0) `periods` periods on, mesh i
  // doing cycles_per_period[i] cycles per period.
  void Skip(const std::vector<long>& cycles_per_period, long long periods);

 private:
  void FindEnd();
  const TrainTables* t_;
  std::vector<int> segment_;
  std::vector<long> cycle_;
  double start_ = 0.0, end_ = 0.0;
  double merge_ = 0.0;
};

struct TrainStepperOptions {
  double grazing_rate_tolerance = 1e-9;         // m/s, >= 0
  long max_events_per_segment = 1000;           // beyond this Run() stops with kTooManyEvents; >= 1
  EventMethod events = EventMethod::kSpectral;  // V3; V2 and V1 for validation
  // Certified jumps of whole common periods in the unrecorded transient (V3 only; see above).
  bool jumps = true;
  // The cycle map is built only when the common period has at most this many grid segments
  // (cost, once: one expm and one sub-step walk per grid segment, ~7x the cost of stepping the
  // segment; up to 64 MiB of propagators during the build at state dimension 8). >= 1.
  long max_cycle_map_segments = 100000;
  // A certificate (and the map's build) is tried only when at least this many whole common
  // periods are left before the recording: the build costs about 7 stepped periods. >= 1.
  long min_jump_periods = 8;
  // Share of each mesh's orbit margin kept free of the transient's bound. In [0, 1).
  double jump_margin_fraction = 0.01;
  // Segment-run fusion on unrecorded time (V3 only; see above): runs of up to 2^fusion_levels
  // grid segments of the common period (only when it has at most max_cycle_map_segments grid
  // segments). 0 disables it. In [0, 16].
  int fusion_levels = 5;
  // The runs' tables held (beyond it no further run is built; those held stay used). >= 1.
  size_t fusion_limit_bytes = size_t{64} << 20;
  // A run's table is built only when at least this many whole common periods of unrecorded time
  // are left: the tables of one period cost ~23 stepped periods and save ~half of each fused one
  // (two-stage reducer, docs/BENCHMARKS.md). Held tables are used whatever is left. >= 1.
  long fusion_min_periods = 64;
  TrainTableOptions tables;
  // Checked at every grid segment and per grid segment of a cycle map's or fused run's build:
  // Run() throws RunCancelled once set (a caller's Ctrl-C). Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  void Validate() const;
};

struct TrainStepperSummary {
  // kOutOfRange: a mesh's displacement passed its displacement_limit (SolverStatus::kOutOfRange).
  enum class Info { kSuccess, kTooManyEvents, kOutOfRange };
  // The outcome of certified jumps (the last reason when none was made).
  enum class Jumps {
    kJumped,
    kDisabled,           // options.jumps off, V1/V2, or a tangent attached
    kNoCommonPeriod,     // TrainTables::common_period is 0 (none within its limit)
    kPeriodTooLong,      // more grid segments per common period than max_cycle_map_segments
    kTransientTooShort,  // no period start in the transient with min_jump_periods periods ahead
    kNoConstantContact,  // no whole transient period with every mesh in one contact state
    kMapRefused,         // the cycle map has no usable orbit (cycle_map_info says why)
    kNotCertified,       // the transient's bound reached an orbit margin at every try
  };
  Info info = Info::kSuccess;
  // kTooManyEvents: the grid segment [stopped_from, stopped_to] (s) where the run stopped, and the
  // limit its events passed (TrainStepperOptions::max_events_per_segment). kOutOfRange: the time
  // in stopped_from, the contact in stopped_on_mesh, and its gap and limit (m; a coupling's stage,
  // out_of_range_twist: rad).
  double stopped_from = 0.0, stopped_to = 0.0;
  long event_limit = 0;
  std::string stopped_on_mesh;  // the mesh of the last event or grazing before the stop
  double out_of_range_gap = 0.0, out_of_range_limit = 0.0;
  bool out_of_range_twist = false;
  Jumps jumps = Jumps::kNoConstantContact;
  long jumped_periods = 0;      // common periods jumped
  double jumped_time = 0.0;     // s
  long period_starts = 0;       // period starts with min_jump_periods periods ahead
  long certificates = 0;        // certificates tried
  long cycle_map_builds = 0;    // cycle maps built (one per contact combination tried)
  long cycle_map_segments = 0;  // grid segments per common period (0: not counted)
  size_t cycle_map_bytes = 0;   // the cycle map held
  TrainCycleMap::Info cycle_map_info = TrainCycleMap::Info::kSuccess;  // of the last map built
  // Segment-run fusion: runs applied, the grid segments they covered (also in grid_segments),
  // grid segment starts tried where no run was certified, run tables built and their bytes.
  long fused_runs = 0, fused_grid_segments = 0, fusion_refusals = 0, fusion_tables = 0;
  size_t fusion_bytes = 0;
  long grid_segments = 0;
  long events = 0, simultaneous_events = 0, grazing = 0;
  long start_switches = 0;   // states switched at once at a segment start
  long dense_pieces = 0;     // pieces propagated on the dense (Taylor) path
  long dyadic_substeps = 0;  // V1: flagged sub-steps walked on the dyadic grid
  long dyadic_matvecs = 0;   // V1: cell maps applied in those walks (bisections included)
  long recenterings = 0;
  double simulated_time = 0.0;  // s
  TrainCacheSummary cache;
};

// "success" | "too many events" | "out of range".
const char* TrainStepperInfoName(TrainStepperSummary::Info info);
// Why a run stopped, in words (empty on kSuccess): the reason and where, e.g. "more than 1000
// contact events in the 2.31e-05 s grid segment starting at t = 0.01234567891 s".
std::string TrainStepperMessage(const TrainStepperSummary& summary);

// Static equilibrium at t = 0 with each mesh on the flank its load presses beyond the gap's
// rounding floor (drive first, a mesh pulled on the back flank, a mesh that carries no force
// free), centred (r~ x = 0); free meshes in the middle of their backlash along the directions the
// contacts leave free (docs/gear-trains.md, "Initial state").
std::pair<Eigen::VectorXd, std::vector<ContactState>> TrainStaticState(const TrainTables& tables);
// The loaded contact states: every gear mesh in drive, each coupling stage as at the static state
// (engaged where the static twist passes it): the tuple a loaded train's modes are taken in.
std::vector<ContactState> LoadedContactStates(const TrainTables& tables);

class TrainStepper {
 public:
  static constexpr double kSimultaneous = 1e-12;  // relative to the grid segment length
  // The dense path's Taylor polynomial: its remainder, e^q q^21 / 21! ||S z|| with q = ||S A S^-1||
  // d
  // <= 1.5 (TrainSystem::substep), is below 4.4e-16 ||S z||: rounding.
  static constexpr int kTaylorTerms = 20;
  static constexpr int kRootSamples = 16;  // samples per sub-step of the V2 root search
  static constexpr int kDyadicLevels = 34;
  TrainStepper(const TrainTables& tables, const TrainStepperOptions& options,
               const Eigen::VectorXd& z0, const std::vector<ContactState>& states0);
  ~TrainStepper();
  // Advances to `end_time` (s); the recorder (optional) sees every piece, sample and event. A
  // certified jump may carry the state up to the recorder's start_time() (end_time without a
  // recorder), so time() can end beyond end_time when the recording starts later.
  bool Run(double end_time, TrainRecorder* recorder = nullptr);

  // Tangent columns advanced with the state (train_tangents.h); nullptr detaches. Not owned.
  void AttachTangent(TrainTangentPropagator* tangent) { tangent_ = tangent; }

  // Restarts at t = 0 from z0 in states0, keeping the cache (the tuples already built).
  void Reset(const Eigen::VectorXd& z0, const std::vector<ContactState>& states0);

  double time() const { return time_; }
  const Eigen::VectorXd& state() const { return z_; }
  const std::vector<ContactState>& states() const { return states_; }
  TrainStepperSummary summary() const;

 private:
  bool AdvanceGridSegment(double until, TrainRecorder* recorder);
  // One piece on the current tuple, up to its first event (or grazing touch) or `remaining`:
  // returns the time advanced.
  double AdvanceSpectral(const TrainSystem& sys, double remaining, TrainRecorder* rec);
  double AdvanceDense(const TrainSystem& sys, double remaining, TrainRecorder* rec);
  double AdvanceDyadic(const TrainSystem& sys, double remaining, TrainRecorder* rec);
  // Fills taylor_ with A^k z / k!, k = 0..kTaylorTerms (the dense path's polynomial).
  void TaylorColumns(const TrainSystem& sys);
  // The first wall (of any mesh) that z1 is outside of, as (mesh, wall), or mesh -1. A gap that
  // turned back towards a wall between z and z1 sets `turned`: any turn when screening a sub-step
  // (walk_cell = 0); in the dyadic walk (walk_cell = the cell length tau) only a turn whose
  // excursion bound reaches the wall, sign g(z) + 2 tau sign g'(z) > 0 (g' falls from g'(z) to
  // below 0 within tau, so the gap rises by at most tau g'(z); 2 for margin). A turn far from a
  // wall, or one at a rate at rounding level (an inflection), would otherwise be bisected to
  // the finest cell at every step of a long stretch.
  struct WallHit {
    int mesh = -1;
    ContactState target = ContactState::kFree;
  };
  WallHit Suspect(const Eigen::VectorXd& z, const Eigen::VectorXd& z1, double walk_cell,
                  bool& turned) const;
  // V1: the gap of `hit`'s mesh moves by less than kResolvableRounding times its rounding floor
  // from z to z1 (a step's ends): a finer cell cannot place the crossing better (its state change
  // is lost in rounding, and bisecting further would crawl through 2^34 cells that do not move z).
  // The event goes at the cell's end, within that rounding-level time. The gap's change, not its
  // rate at one end: near the apex of a brief excursion beyond a wall the rate at z1 is ~0 while
  // the step still holds the crossing.
  static constexpr double kResolvableRounding = 4.0;
  bool BelowGapRounding(const WallHit& hit, const Eigen::VectorXd& z,
                        const Eigen::VectorXd& z1) const;
  bool SwitchOutside(TrainRecorder* rec);
  // A wall of a mesh's state: gap g+ (drive) or g-; sign * g > 0 is outside; the state beyond.
  struct Wall {
    bool drive = true;
    double sign = 1.0;
    ContactState target = ContactState::kFree;
  };
  int Walls(int mesh, Wall walls[2]) const;
  void Switch(int mesh, ContactState to, double time, TrainRecorder* rec);
  // A grazing touch of `mesh` at `time`: counted (as an event of the segment), the state kept.
  void Graze(int mesh, double time, TrainRecorder* rec);
  // The summary's message when a grid segment exceeded max_events_per_segment.
  // out = sum_k taylor_.col(k) tau^k (Horner).
  void TaylorValue(double tau, Eigen::VectorXd& out) const;
  // Hands the piece from z_start (at piece_start, in the current tuple) to the recorder: its
  // exact statistics, and its samples (on the decomposition or on taylor_).
  void Record(const TrainSystem& sys, const Eigen::Ref<const Eigen::VectorXd>& z_start,
              double piece_start, double length, bool spectral, TrainRecorder* rec);
  void Recenter();
  // At a common period's start: certifies permanent contact and jumps (train_cycle_jump.cc).
  bool AtPeriodStart() const;
  // False (info kOutOfRange) once a mesh's gap passes its displacement_limit. Checked every
  // kRangeCheckSegments grid segments and at the end of Run: a diverging run stops long before
  // it overflows.
  bool WithinRange();
  static constexpr long kRangeCheckSegments = 64;
  long segments_since_range_check_ = 0;
  void TryJump(double end_time, const TrainRecorder* rec);
  void JumpOutcome(TrainStepperSummary& s) const;  // the reason when no period start was tried
  // At a grid segment start: a certified segment run, applied (train_segment_runs.cc); returns
  // the grid segments it covered (0: none).
  long FusedRun(double end_time, const TrainRecorder* rec);
  void FusionOutcome(TrainStepperSummary& s) const;

  const TrainTables& t_;
  TrainStepperOptions options_;
  TrainSystemCache cache_;
  TrainGrid grid_;
  Eigen::VectorXd z_, w_, wt_, scratch_, zs_;
  Eigen::MatrixXd taylor_;
  Eigen::MatrixXd substep_map_;                 // V1: expm(A d) of the current sub-step
  std::vector<Eigen::MatrixXd> dyadic_levels_;  // V1: expm(A d 2^-(l+1)), l = 0..33
  Eigen::VectorXd z1_;
  std::vector<ContactState> states_;
  std::vector<double> roots_;
  std::vector<Wall> root_walls_;
  TupleKey key_;
  double time_ = 0.0;
  double recenter_period_ = 0.0, next_recenter_ = 0.0;
  long events_this_segment_ = 0;
  int last_event_mesh_ = -1;  // the mesh of the last event or grazing (the stop message names it)
  TrainStepperSummary summary_;
  TrainTangentPropagator* tangent_ = nullptr;
  // Jumps: whole cycles of each mesh per common period, the map of the last contact
  // combination tried, and the events (and grazings) counted at the last period start.
  std::vector<long> period_cycles_;
  std::unique_ptr<TrainCycleMap> cycle_map_;
  long period_segments_ = 0;  // grid segments per common period (0: not counted yet)
  long events_at_period_ = 0;
  std::unique_ptr<TrainSegmentRuns> fusion_;
  long period_position_ = 0;  // the grid segment's index in the common period
};

}  // namespace gearnvh
