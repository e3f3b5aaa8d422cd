// Exact piecewise-LTI propagation with closed-form-accurate event location (docs/design.md §4).
//
// Stepping loop, per mesh cycle and segment j, in contact state sigma (ExactStepper::Run):
//   1. kFused, unrecorded cycle: try the longest certified run of segments from j in one matvec
//      (segment_runs.h); taken when the certificate and the end-state check hold.
//   2. the inputs u (engine excitation, manufacturing error) <- their means over segment j
//   3. certified permanent contact (kFused, cycle_map.h): the whole segment in one matvec.
//   4. otherwise, by EventMethod:
//      kSpectral (V3, default): the whole segment at once; the first root of the closed-form gap
//        in decoupled coordinates (spectral_gap.h) is the event; two matvecs without an event.
//      kTaylor (V2) / kDyadic (V1): N_j sub-steps of length D = h_j / N_j, one matvec each; a
//        sub-step whose endpoint signs and rates show a wall may have been reached is searched on
//        the Taylor polynomial z(tau) = sum_k A^k z tau^k / k! (rho(A) D <= 1/2, 18 terms reach
//        rounding; sampling + safeguarded Newton), or by dyadic bisection for V1.
//      At an event: z <- z(t*), sigma <- new state, log it, continue the segment in the new state.
//   5. at the cycle end: recentre the pair's free rotation.
// Given the piecewise-constant segment model, event times and states are exact to rounding.
// A state found outside its wall at the start of a (sub-)step by more than the wall tolerance
// 1e-12 b + 64 eps sum_i |c_i z_i| (the rounding floor of the gap, whose terms grow as the pair's
// free rotation drifts) switches at once: the contact state is the gap's sign (the unloaded error
// e_j jumps at segment boundaries).
// Wall triggers: free -> drive when g+ rises through 0, free -> back when g- falls through 0,
// drive -> free when g+ falls through 0, back -> free when g- rises through 0. A root with
// |g'| below grazing_rate_tolerance is a grazing contact: counted, and the state is kept.
// No heap allocation happens inside the loop once SimulateExact has set up its workspace.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <functional>
#include <stdexcept>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/solver/exact_recorder.h"
#include "gearnvh/solver/segment_runs.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/spectral_gap.h"

namespace gearnvh {

// kStepped: the event-locating sub-step loop everywhere. kFused: additionally (1) when the run
// starts in contact with no engine excitation or manufacturing error and ConstantContactCycle
// certifies that contact is kept forever, the transient cycles are jumped in O(1) and recorded
// cycles advance one matvec per segment; (2) on cycles whose samples are not recorded, certified
// runs of 2..32 segments advance in one matvec (segment_runs.h). Both use the same propagator
// products, so the result is unchanged to rounding.
enum class SolverMethod { kStepped, kFused };
const char* SolverMethodName(SolverMethod m);

// How events are located (all three give the same event times; the ladder and the tests compare
// them).
// kSpectral (V3, default): per whole segment, closed-form gap in the decoupled coordinates of the
//   generator (spectral_gap.h): derivative-bound prescreen, certified monotone sub-intervals,
//   safeguarded Newton; two matvecs per segment; exact event times. A (segment, state) whose
//   decomposition is ill-conditioned (cond(S) > spectral_max_condition, close eigenvalues of
//   different blocks) falls back to the kTaylor path for that segment; the summary counts them.
// kTaylor (V2): sub-steps of length D (rho(A) D <= 1/2); the endpoint signs and rates of each
//   sub-step certify that no wall was reached; a flagged sub-step is searched on the Taylor
//   polynomial of the state (sampling, interior extrema, safeguarded Newton), exact to rounding.
// kDyadic (V1 baseline): bisection on dense dyadic propagators expm(A D / 2^l), l = 1..34; event
//   times quantised to D 2^-34; tables grow by 34 matrices per segment and state (refused above
//   256 MiB).
enum class EventMethod { kSpectral, kTaylor, kDyadic };
const char* EventMethodName(EventMethod m);

struct SolverOptions {
  SolverMethod method = SolverMethod::kFused;
  EventMethod events = EventMethod::kSpectral;
  // kSpectral: decompositions with |S|_1 |S^-1|_1 above this fall back to kTaylor (state error
  // ~ cond(S) eps).
  double spectral_max_condition = 1e6;  // >= 1
  long cycles = 100;                    // mesh cycles recorded after the transient; >= 1
  long transient_cycles = 0;            // mesh cycles run first and not recorded; >= 0
  // Recorded cycles: exact statistics and uniform samples (samples_per_cycle per mesh cycle,
  // evaluated exactly at their times; exact_recorder.h).
  bool record_trajectory = true;
  int samples_per_cycle = 32;            // >= 1
  long max_events_per_cycle = 1000;      // beyond this the run stops with kTooManyEvents; >= 1
  double grazing_rate_tolerance = 1e-9;  // |g'| (m/s) below which a root is a grazing touch; >= 0
  // Memory bounds of the recorded trajectory (reserved up front, so the loop never allocates):
  // samples beyond max_trajectory_samples (~64 B each) and events beyond max_logged_events (~32 B
  // each) are not stored; counts stay exact and the summary says the trajectory was truncated.
  long max_trajectory_samples = 4'000'000;  // >= 0
  long max_logged_events = 1'000'000;       // >= 0
  // The linear backlash-free reference: the state never changes (the contact spring of the
  // starting state also acts in tension), one propagator matvec per segment, no events.
  bool ignore_walls = false;
  // kFused: segment runs of up to 2^fusion_levels segments (0 disables them); in [0, 5].
  int fusion_levels = 5;
  // Cancellation (an interactive caller's Ctrl-C): polled at the start of every mesh cycle by
  // ExactStepper::Run, which throws RunCancelled once it is set. Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  bool Cancelled() const { return cancel != nullptr && cancel->load(std::memory_order_relaxed); }
  void Validate() const;
};

// Thrown by a run whose SolverOptions::cancel was set.
class RunCancelled : public std::runtime_error {
 public:
  RunCancelled() : std::runtime_error("cancelled") {}
};

// The method names of the CLI: v1, v2, v3 (stepped with that event path) and fused (v3 + fusion).
// Throws InputError naming `field` for anything else.
void ApplyMethodName(const std::string& name, SolverOptions& options,
                     const std::string& field = "--method");

enum class SolverStatus { kSuccess, kTooManyEvents };
const char* SolverStatusName(SolverStatus s);

struct SolverSummary {
  SolverStatus status = SolverStatus::kSuccess;
  std::string message;
  long mesh_cycles = 0;  // recorded + transient
  long drive_impacts = 0, back_impacts = 0, separations = 0, grazing = 0;
  long events = 0;
  long matvecs = 0;
  long fused_cycles = 0;        // cycles advanced one matvec per segment (certified contact)
  long run_fused_segments = 0;  // segments advanced inside certified segment runs (kFused)
  long jumped_cycles = 0;       // cycles skipped by a certified O(1) jump
  bool contact_certified = false;
  double events_per_cycle = 0.0, matvec_per_cycle = 0.0;
  double simulated_s = 0.0, wall_s = 0.0, real_time_ratio = 0.0;
  long recorded_cycles = 0;
  double recorded_s = 0.0;   // simulated time of the recorded cycles
  double separated_s = 0.0;  // recorded time spent in the free state (exact, from event times)
  size_t table_bytes = 0;
  int spectral_fallback_systems = 0;    // (segment, state) pairs located by kTaylor instead of V3
  double spectral_max_condition = 0.0;  // largest cond(S) among the decompositions used
  bool trajectory_truncated = false;    // a memory bound of SolverOptions was reached
  // Smallest |g'| (m/s) at a state-triggered contact change so far (infinity when none): how
  // close the run came to a grazing contact, where saltation matrices blow up.
  double min_event_rate = std::numeric_limits<double>::infinity();
};

struct SolverResult {
  Trajectory trajectory;
  SolverSummary summary;
  Eigen::VectorXd final_state;
  ContactState final_contact = ContactState::kFree;
};

// Static equilibrium in drive contact when the load closes the gap (least-squares on the pair's
// free rotation), otherwise rest in the middle of the backlash. Returns z (size m) and the state.
std::pair<Eigen::VectorXd, ContactState> StaticInitialState(const SegmentTables& tables);
// The drive-contact equilibrium of segment 0 whatever the sign of the gap (the start of the
// linear reference with ignore_walls).
Eigen::VectorXd DriveEquilibrium(const SegmentTables& tables);

// The stepping loop itself. Construction allocates every buffer; Run() does not allocate (the
// trajectory's capacity is reserved up front: `reserve_samples` uniform samples and
// `reserve_events` events; beyond them they are counted, not stored).
class ExactStepper {
 public:
  ExactStepper(const SegmentTables& tables, const SolverOptions& options, const Eigen::VectorXd& z0,
               ContactState state0, size_t reserve_samples, size_t reserve_events);
  // Advances `cycles` whole mesh cycles; records samples/events when `record`. Returns false when
  // a cycle exceeded options.max_events_per_cycle.
  bool Run(long cycles, bool record);
  // Certified permanent contact: cycles advance one matvec per segment from now on.
  void SetFusedContact(bool fused) { fused_ = fused; }
  // Replaces the state (after a certified jump) and advances the clock by whole cycles.
  void JumpTo(const Eigen::VectorXd& z, long cycles);
  // Tangent propagation (docs/design.md §5). The columns of *tangent (m x p, zero in the constant and
  // excitation slots) are advanced with the state by the same propagators, so they carry the
  // derivative of the state with respect to the initial state. Events:
  //   state-triggered crossing (a located root)   V <- S V,  S = I + (f+ - f-) n^T / (n^T f-),
  //     n the crossing gap row, f-/f+ = A_from z / A_to z at the event (n^T f- = g' != 0);
  //   time-triggered switch (a segment starts outside a wall because e_j jumped)   S = I;
  //   grazing touch (state kept)                  nothing.
  // At every cycle end the columns are projected onto the quotient by the pair's free rotation
  // (FreeRotationProjector): its position and velocity are neutral (multiplier 1) and change no
  // gap or force. Attach allocates; Run() then still does not. nullptr detaches.
  void AttachTangent(Eigen::MatrixXd* tangent);
  // Starts again from z at time 0 in `state`: clock, counts and trajectory are cleared; the
  // tables and the decompositions are kept (shooting evaluates the same map many times).
  void Restart(const Eigen::VectorXd& z, ContactState state);

  const Eigen::VectorXd& state() const { return z_; }
  ContactState contact() const { return contact_; }
  double time() const { return time_; }
  SolverSummary& summary() { return summary_; }
  // Recorded time in free flight so far, including a flight still open at the current time.
  double SeparatedTime() const {
    return summary_.separated_s + (free_since_ >= 0.0 ? time_ - free_since_ : 0.0);
  }
  Trajectory& trajectory() { return trajectory_; }

 private:
  static constexpr int kTaylorTerms = 18;
  static constexpr int kRootSamples = 16;
  bool PossibleEvent(const SegmentSystem& sys, bool segment_start) const;
  double WallTolerance(const Eigen::RowVectorXd& row) const;
  void AdvanceExact(int segment, double start, double length, bool record);
  void AdvanceDyadic(int segment, double start, bool record);
  void AdvanceSpectral(int segment, double start, bool record);
  // The rest of a segment from `done` by the kTaylor search in chunks of one sub-step.
  void AdvanceTaylorFrom(int segment, double start, double done, bool record);
  // The first wall (0/1) that z is outside of (beyond the wall tolerance when asked), or -1.
  int Outside(const SegmentSystem& sys, const Eigen::VectorXd& z, bool with_tolerance) const;
  void SwitchState(const SegmentSystem& sys, int wall, double time, bool record,
                   bool state_triggered);
  void PropagateTangent(const Eigen::MatrixXd& propagator);            // V <- Phi V
  void PropagateTangentTaylor(const Eigen::MatrixXd& A, double step);  // V <- expm(A step) V
  void PropagateTangentDecoupled(const SpectralDecomposition& d, double step);
  bool TooManyEvents();  // sets the status and message; returns false
  // The unloaded error e_j jumps at a segment boundary: a start outside a wall (beyond the wall
  // tolerance) switches at once.
  void SwitchIfOutsideAtStart(int segment, double start, bool record);
  // Recorded pieces (exact_recorder.h): a piece starts at a segment start or an event and ends at
  // the next event or the segment end.
  void BeginPiece(double time);
  void EndPiece(double time);

  const SegmentTables& t_;
  SolverOptions options_;
  Eigen::VectorXd z_, z1_;
  Eigen::MatrixXd taylor_;  // m x (kTaylorTerms + 1): A^k z / k!
  static constexpr int kDyadicLevels = 34;
  // kDyadic: dyadic_[segment][state][l] = expm(A D 2^-(l+1)), l = 0..kDyadicLevels-1.
  std::vector<std::array<std::vector<Eigen::MatrixXd>, 3>> dyadic_;
  Eigen::VectorXd za_, zb_;
  // kSpectral: per segment and state, the decomposition and the closed forms of both gap rows.
  struct SpectralSystem {
    SpectralDecomposition decomposition;
    ClosedFormGap drive, back;
    bool ok = false;
  };
  std::vector<std::array<SpectralSystem, 3>> spectral_;
  Eigen::VectorXd w_, wt_, scratch_;
  ContactState contact_;
  double gap_tolerance_;  // m: a start this far outside a wall is an immediate event
  double time_ = 0.0;
  long cycle_ = 0;
  long events_this_cycle_ = 0;
  double free_since_ = -1.0;  // start of the current recorded free flight, or -1
  bool fused_ = false;
  // kFused: certified segment runs (segment_runs.h), per contact state; used on cycles whose
  // samples are not recorded and without a tangent.
  std::array<SegmentRunTable, 3> runs_;
  bool runs_built_ = false;
  Eigen::VectorXd run_scratch_, input_scratch_;
  int segment_ = 0;  // the segment being advanced
  Eigen::MatrixXd* tangent_ = nullptr;
  Eigen::MatrixXd tangent_next_, tangent_w_;
  Eigen::VectorXd f_minus_, f_plus_, tangent_col_;
  SolverSummary summary_;
  Trajectory trajectory_;
  std::optional<ExactRecorder> recorder_;
  bool recording_ = false;  // the recorded window has started
  bool piece_open_ = false;
  Eigen::VectorXd piece_z_;
  double piece_start_ = 0.0;
  ContactState piece_state_ = ContactState::kFree;
};

// Progress callback: (mesh cycles done, total) — called about 100 times per run; may be empty.
using ProgressCallback = std::function<void(long, long)>;

SolverResult SimulateExact(const SegmentTables& tables, const Eigen::VectorXd& z0,
                           ContactState state0, const SolverOptions& options,
                           const ProgressCallback& progress = {});

}  // namespace gearnvh
