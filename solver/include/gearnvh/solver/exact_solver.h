// Exact piecewise-LTI propagation with closed-form-accurate event location (docs/design.md §4).
//
// Within segment j of the mesh cycle and contact state sigma the model is LTI, z' = A_{j,sigma} z,
// so z(t) = expm(A t) z is exact; the contact state changes when a gap row crosses its wall. The
// solver is split along its seams (Drake systems/analysis style):
//   event_locator.h      the EventLocator interface (DoStep over one segment, events reported to
//                        an EventHandler) and one class per method: SpectralLocator (V3,
//                        spectral_locator.h), TaylorLocator (V2), DyadicLocator (V1); each owns
//                        its tables.
//   tangent_propagator.h tangent columns: the same maps, saltation at state-triggered events.
//   segment_fusion.h     certified segment runs and certified permanent contact.
//   run_recording.h      pieces for the ExactRecorder, event counts and log, separated time.
//   ExactStepper (here)  the loop over cycles and segments that ties them together, and the
//                        EventHandler that applies each event.
// Per mesh cycle and segment j, in contact state sigma (ExactStepper::Run):
//   1. kFused, unrecorded cycle, no tangent: the longest certified run of segments from j in one
//      matvec (segment_runs.h); taken when the certificate and the end-state check hold.
//   2. the inputs u (engine excitation, manufacturing error) <- their means over segment j
//   3. certified permanent contact (kFused, cycle_map.h) or ignore_walls: the whole segment in one
//      matvec; otherwise the locator of SolverOptions::events advances the segment:
//      kSpectral (V3, default): the whole segment at once; the first root of the closed-form gap
//        in decoupled coordinates (spectral_gap.h) is the event; two matvecs without an event.
//      kTaylor (V2) / kDyadic (V1): N_j sub-steps of length D = h_j / N_j, one matvec each; a
//        sub-step whose endpoint signs and rates show a wall may have been reached is searched on
//        the Taylor polynomial z(tau) = sum_k A^k z tau^k / k! (rho(A) D <= 1/2, 18 terms reach
//        rounding; sampling + safeguarded Newton), or by dyadic bisection for V1.
//      At an event: z <- z(t*), sigma <- new state, log it, continue the segment in the new state.
//   4. at the cycle end: recentre the pair's free rotation.
// Certified permanent contact with its cycle map (kFused, SolverOptions::cycle_rows): the whole
// cycle is one cycle-map matvec instead, and a recorded cycle is recorded by output rows on its
// start state (cycle_output_rows.h).
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
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "gearnvh/solver/cycle_map.h"
#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/exact_recorder.h"
#include "gearnvh/solver/run_recording.h"
#include "gearnvh/solver/segment_fusion.h"
#include "gearnvh/solver/segment_runs.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/spectral_gap.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

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

// The stepping loop itself: a thin orchestrator over the pieces it delegates to. Per mesh cycle and
// segment j:
//   1. SegmentFusion::TryRun (kFused, unrecorded cycle, no tangent): a certified run of segments.
//   2. the inputs u of segment j are set in z (SegmentTables::SetInputs).
//   3. SegmentFusion::AdvanceWhole (certified permanent contact, ignore_walls): one matvec; or
//      EventLocator::DoStep (V1/V2/V3, event_locator.h): the segment with its events.
//   4. the recorded piece of the segment goes to RunRecording (recorded cycles).
// At the cycle end the free rotation is recentred (and projected out of the tangent). Each cycle
// is dispatched to the concrete locator class (StepCycleWith), so the per-segment DoStep is a
// direct call; whole-segment cycles (permanent contact, ignore_walls) run a loop of their own.
// The stepper is the locators' EventHandler: at each event it switches the contact state, applies
// the saltation (TangentPropagator), counts and records, and stops after max_events_per_cycle.
// Construction allocates every buffer; Run() does not allocate (the trajectory's capacity is
// reserved up front: `reserve_samples` uniform samples and `reserve_events` events; beyond them
// they are counted, not stored).
class ExactStepper : private EventHandler {
 public:
  ExactStepper(const SegmentTables& tables, const SolverOptions& options, const Eigen::VectorXd& z0,
               ContactState state0, size_t reserve_samples, size_t reserve_events);
  ExactStepper(const ExactStepper&) = delete;
  ExactStepper& operator=(const ExactStepper&) = delete;
  // Advances `cycles` whole mesh cycles; records samples/events when `record`. Returns false when
  // a cycle exceeded options.max_events_per_cycle.
  bool Run(long cycles, bool record);
  // Certified permanent contact: cycles advance one matvec per segment from now on.
  void SetFusedContact(bool fused) { fusion_.SetPermanentContact(fused); }
  // With SetFusedContact(true) and the certified cycle map of the current contact state (not
  // owned; nullptr: none): each cycle in one cycle-map matvec, recorded cycles by output rows
  // (cycle_output_rows.h). Not with an attached tangent.
  void SetCycleMap(const ConstantContactCycle* cycle);
  // Replaces the state (after a certified jump) and advances the clock by whole cycles.
  void JumpTo(const Eigen::VectorXd& z, long cycles);
  // Tangent propagation (tangent_propagator.h, docs/design.md §5): the columns of *tangent
  // (m x p, zero in the constant and input slots) are advanced with the state by the same maps, so
  // they carry the derivative of the state with respect to the initial state; saltation at
  // state-triggered events, the identity at time-triggered switches and grazing touches, the
  // projection onto the quotient by the pair's free rotation at every cycle end. Attach
  // allocates; Run() then still does not. nullptr detaches.
  void AttachTangent(Eigen::MatrixXd* tangent);
  // Starts again from z at time 0 in `state`: clock, counts and trajectory are cleared; the
  // tables and the decompositions are kept (shooting evaluates the same map many times).
  void Restart(const Eigen::VectorXd& z, ContactState state);

  const Eigen::VectorXd& state() const { return state_.z; }
  ContactState contact() const { return state_.contact; }
  double time() const { return time_; }
  EventMethod event_method() const { return locator_->method(); }
  SolverSummary& summary() {
    summary_.matvecs = state_.matvecs;
    return summary_;
  }
  // Recorded time in free flight so far, including a flight still open at the current time.
  double SeparatedTime() const { return recording_.SeparatedTime(summary_, time_); }
  Trajectory& trajectory() { return recording_.trajectory(); }

 private:
  // EventHandler.
  bool Switch(int segment, const SegmentSystem& from, const GapWall& wall, double time,
              bool state_triggered) override;
  bool Graze(double time) override;
  // The segments of the current mesh cycle; false when a cycle had too many events.
  bool StepCycle(bool recorded, bool try_runs);
  // StepCycle when every segment is advanced whole (permanent contact, ignore_walls).
  void StepWholeSegments(bool recorded);
  // StepCycle with the concrete (final) locator class: the per-segment DoStep is a direct call.
  template <class Locator>
  bool StepCycleWith(Locator& locator, bool recorded, bool try_runs);
  void EndCycle(bool record);
  bool TooManyEvents();  // sets the status and message; returns false
  bool WithinRange();    // false (status and message set) once a gap passes displacement_limit
  // Copies the table sizes and decomposition counts of the locator (which grow on first visits).
  void UpdateTableStatistics();

  const SegmentTables& t_;
  SolverOptions options_;
  std::unique_ptr<EventLocator> locator_;
  TangentPropagator tangent_;
  SegmentFusion fusion_;
  RunRecording recording_;
  LocatorState state_;               // z, contact state, tangent, matvec count
  SegmentTables::CyclePhase phase_;  // the excitation's phases of the current cycle (SetInputs)
  const ConstantContactCycle* cycle_map_ = nullptr;
  Eigen::VectorXd cycle_end_;
  double time_ = 0.0;
  long cycle_ = 0;
  long events_this_cycle_ = 0;
  bool record_ = false;  // the current Run() counts and logs events
  SolverSummary summary_;
};

// Progress callback: (mesh cycles done, total) — called about 100 times per run; may be empty.
using ProgressCallback = std::function<void(long, long)>;

SolverResult SimulateExact(const SegmentTables& tables, const Eigen::VectorXd& z0,
                           ContactState state0, const SolverOptions& options,
                           const ProgressCallback& progress = {});

}  // namespace gearnvh
