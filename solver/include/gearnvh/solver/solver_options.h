// Options, status and summary of the exact solver (exact_solver.h; docs/solver.md).
#pragma once

#include <atomic>
#include <limits>
#include <stdexcept>
#include <string>

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
  // kSpectral: a segment without an event hands its state to the next segment in decoupled
  // coordinates (one matvec instead of two; spectral_locator.h) where the first-order bound of
  // the relative state error that step adds is at most this; 0 disables it.
  double carry_max_error = 1e-7;  // >= 0
  long cycles = 100;              // mesh cycles recorded after the transient; >= 1
  long transient_cycles = 0;      // mesh cycles run first and not recorded; >= 0
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
  // kFused, certified permanent contact: each mesh cycle in one cycle-map matvec, and recorded
  // cycles by output rows on the cycle's start state (cycle_output_rows.h); equal to the
  // piece-by-piece recording to rounding. false: one matvec per segment, recorded piece by piece.
  bool cycle_rows = true;
  // Cancellation (an interactive caller's Ctrl-C): polled (ThrowIfCancelled) at the start of every
  // mesh cycle by ExactStepper::Run and per segment while the run's tables are built (locator,
  // segment runs, recorder rows, cycle map, output rows). Not owned; null: never cancelled.
  const std::atomic<bool>* cancel = nullptr;
  void Validate() const;
};

// Thrown by a run whose SolverOptions::cancel was set.
class RunCancelled : public std::runtime_error {
 public:
  RunCancelled() : std::runtime_error("cancelled") {}
};

// Throws RunCancelled once *cancel is set (null: never). Called once per step of every loop of a
// run or of its set-up that can last more than ~0.1 s on a large model (a segment, a grid segment,
// a cycle, a CVODE step, a tier, a speed), so a caller waiting on Ctrl-C is answered within one
// such step.
inline void ThrowIfCancelled(const std::atomic<bool>* cancel) {
  if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) throw RunCancelled();
}

// The rungs of the validation ladder as one choice: kV1, kV2, kV3 step (kStepped) with the
// kDyadic, kTaylor, kSpectral event path; kFused is kSpectral events plus kFused. Callers that
// only locate events (Lyapunov exponents, orbits, the atlas, every train run) take EventMethodOf.
enum class LadderMethod { kV1, kV2, kV3, kFused };
inline constexpr LadderMethod kLadderMethods[] = {LadderMethod::kV1, LadderMethod::kV2,
                                                  LadderMethod::kV3, LadderMethod::kFused};
// "v1", "v2", "v3", "fused": the names results documents and tables print.
const char* LadderMethodName(LadderMethod m);
EventMethod EventMethodOf(LadderMethod m);
// Sets options.method and options.events to the rung's.
void ApplyLadderMethod(LadderMethod m, SolverOptions& options);

// kOutOfRange: a mesh's relative displacement left the range the model describes (the teeth's whole
// depth beyond either wall), as when the response grows without bound; the run stops there.
enum class SolverStatus { kSuccess, kTooManyEvents, kOutOfRange };
const char* SolverStatusName(SolverStatus s);
// The kOutOfRange message: `where` ("at mesh cycle 12", "on mesh g1-g2") and the time, the gap
// reached and the limit (m), for every gearbox alike.
std::string OutOfRangeMessage(const std::string& where, double time, double gap, double limit);

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
  // V3 steps carried in decoupled coordinates (spectral_locator.h): the (segment,
  // state) pairs that carry and the largest first-order bound of the relative state error one
  // carried step adds.
  int carried_systems = 0;
  double carry_error_bound = 0.0;
  bool trajectory_truncated = false;  // a memory bound of SolverOptions was reached
  // Smallest |g'| (m/s) at a state-triggered contact change so far (infinity when none): how
  // close the run came to a grazing contact, where saltation matrices blow up.
  double min_event_rate = std::numeric_limits<double>::infinity();
};

}  // namespace gearnvh
