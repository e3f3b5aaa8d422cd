// Event location over one segment of the piecewise-LTI model (docs/design.md §4.2, §4.4).
//
// Within segment j the state obeys z' = A_{j,sigma} z in contact state sigma. A state can cross
// the gap rows (walls) of its state: an event happens when sign * (row . z) rises through 0
//   free  -> drive when g+ rises through 0,    free -> back when g- falls through 0,
//   drive -> free  when g+ falls through 0,    back -> free when g- rises through 0,
// and the contact state becomes the wall's target. An EventLocator advances the state over a
// whole segment (DoStep, one call per segment, like Drake's IntegratorBase::DoStep), finds every
// event on the way in time order and reports each one to an EventHandler, which applies it
// (contact switch, saltation of the tangent, counts, recording) and says whether to go on; the
// locator then continues the segment in the new contact state. Given the piecewise-constant model
// the three locators give the same event times and states (the conformance suite compares them):
//   SpectralLocator (V3, default): closed-form gap in the decoupled coordinates of the generator
//     per whole segment (spectral_gap.h), exact to rounding, two matvecs without an event. An
//     ill-conditioned (segment, state) falls back to the TaylorLocator's search.
//   TaylorLocator (V2): N_j sub-steps of length D (rho(A) D <= 1/2), one matvec each; a sub-step
//     whose end-point signs and rates show that a wall may have been reached is searched on the
//     Taylor polynomial z(tau) = sum_k A^k z tau^k / k! (18 terms; sampling + safeguarded Newton),
//     exact to rounding.
//   DyadicLocator (V1 baseline): the same sub-step screen; a flagged sub-step is bisected on dense
//     dyadic propagators expm(A D 2^-l), l = 1..34, so event times are quantised to D 2^-34.
// A state found outside a wall at a (sub-)step start by more than the wall tolerance
// 1e-12 b + 64 eps sum_i |c_i z_i| (the gap's rounding floor) switches at once (time-triggered:
// the unloaded error e_j jumps at segment boundaries). A root with |g'| <= grazing_rate_tolerance
// that curves back inside is a grazing touch: reported, the state is kept.
// DoStep does not allocate: each locator owns its tables and workspace.
//
// Gear trains: the locators see a contact state only through its list of GapWalls (each with its
// row, rate row, trigger sign, target and index into the per-(segment, state) gap set) and loop
// over that list; the earliest root over all walls is the event. A train stepper adopts this
// interface by giving each wall the mesh it belongs to (target = that mesh's new state), by
// keying the systems and the locator tables on (segment, contact combination) instead of
// (segment, sigma), and by listing the walls of every mesh in ActiveWalls: the search loops, the
// sub-step screen and the handler protocol stay as they are.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstddef>
#include <memory>
#include <vector>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/spectral_gap.h"

namespace gearnvh {

class TangentPropagator;

// One gap row a contact state can cross: the event is when sign * (row . z) rises through 0.
struct GapWall {
  const Eigen::RowVectorXd* row = nullptr;   // gap g = row . z
  const Eigen::RowVectorXd* rate = nullptr;  // g' = rate . z
  double sign = 1.0;
  ContactState target = ContactState::kFree;  // the contact state after the crossing
  int gap = 0;                                // index into the gap set (GapRow): 0 g+, 1 g-
};

inline constexpr int kMaxWalls = 2;
inline constexpr int kGapRows = 2;
// The walls of `state` in segment system `sys` (free: both flanks; contact: its own flank).
int ActiveWalls(const SegmentSystem& sys, ContactState state, GapWall out[kMaxWalls]);
// The gap set of a pair: 0 -> g+ (drive flank), 1 -> g- (back flank).
const Eigen::RowVectorXd& GapRow(const SegmentSystem& sys, int gap);

// What a locator advances: the augmented state, its contact state, the tangent (null when none is
// attached; advanced by the same maps) and the running matvec count.
struct LocatorState {
  Eigen::VectorXd z;
  ContactState contact = ContactState::kFree;
  TangentPropagator* tangent = nullptr;
  long matvecs = 0;
};

// Receives the events a locator finds, in time order.
class EventHandler {
 public:
  // state.z has reached `wall` of system `from` (segment `segment`) at absolute time `time`:
  // switch state.contact to wall.target (state_triggered: a located root, with saltation;
  // otherwise a start outside the wall). Returns false when the run must stop.
  virtual bool Switch(int segment, const SegmentSystem& from, const GapWall& wall, double time,
                      bool state_triggered) = 0;
  // A grazing touch at `time` (the state is kept). Returns false when the run must stop.
  virtual bool Graze(double time) = 0;

 protected:
  ~EventHandler() = default;
};

// Tables held by a locator (reported in the solver summary).
struct LocatorStatistics {
  size_t table_bytes = 0;
  int spectral_fallback_systems = 0;    // (segment, state) pairs searched by V2 instead of V3
  double spectral_max_condition = 0.0;  // largest cond(S) among the decompositions used
};

class EventLocator {
 public:
  EventLocator(const SegmentTables& tables, const SolverOptions& options);
  virtual ~EventLocator() = default;
  EventLocator(const EventLocator&) = delete;
  EventLocator& operator=(const EventLocator&) = delete;

  // Advances `state` over the whole of segment `segment`, which starts at absolute time `start`
  // (the inputs of the segment are already set in state.z), reporting every event to `handler`.
  // Returns false as soon as the handler asks to stop.
  virtual bool DoStep(int segment, double start, LocatorState& state, EventHandler& handler) = 0;
  virtual EventMethod method() const = 0;
  const LocatorStatistics& statistics() const { return statistics_; }

 protected:
  // Rounding floor of the gap `row` . z (its terms can be much larger than the gap, e.g. as the
  // pair's free rotation drifts): inside it a state is not moved.
  double WallTolerance(const Eigen::RowVectorXd& row, const Eigen::VectorXd& z) const;
  // The first wall (index into ActiveWalls) that z is outside of, or -1.
  int Outside(const SegmentSystem& sys, ContactState state, const Eigen::VectorXd& z,
              bool with_tolerance) const;
  // The unloaded error e_j jumps at a segment boundary: a start outside a wall (beyond the wall
  // tolerance) switches at once (time-triggered). Returns false when the handler stops the run.
  bool SwitchIfOutsideAtStart(int segment, double start, LocatorState& state,
                              EventHandler& handler) const;

  const SegmentTables& t_;
  double gap_tolerance_;  // m: a start this far outside a wall is an immediate event
  double grazing_rate_tolerance_;
  LocatorStatistics statistics_;
};

// V1 and V2: N_j sub-steps of length D per segment, one matvec each (the sub-step propagator);
// a sub-step is handed to Examine() only if a wall may have been reached: the end point is
// outside, the gap turned towards the wall and back (rates at both ends), or, at a segment start,
// the start itself is outside beyond the wall tolerance.
class SubstepLocator : public EventLocator {
 public:
  SubstepLocator(const SegmentTables& tables, const SolverOptions& options);
  bool DoStep(int segment, double start, LocatorState& state, EventHandler& handler) final;

 protected:
  // Advances state.z over the flagged sub-step [start, start + D] of `segment` exactly.
  virtual bool Examine(int segment, double start, LocatorState& state, EventHandler& handler) = 0;
  Eigen::VectorXd z1_;  // the sub-step end point

 private:
  bool PossibleEvent(const SegmentSystem& sys, const LocatorState& state, bool segment_start) const;
};

// V2: the flagged sub-step is searched on the Taylor polynomial of the state (sampling, interior
// maxima, safeguarded Newton); the state at the root is the same polynomial evaluated there.
class TaylorLocator final : public SubstepLocator {
 public:
  static constexpr EventMethod kMethod = EventMethod::kTaylor;
  static constexpr int kTaylorTerms = 18;  // (rho D)^k / k! with rho D <= 1/2: rounding at 18
  static constexpr int kRootSamples = 16;
  TaylorLocator(const SegmentTables& tables, const SolverOptions& options);
  EventMethod method() const override { return kMethod; }
  // The rest of segment `segment` from `done` (s into it) in chunks of one sub-step, every chunk
  // searched (the V3 fallback for an ill-conditioned decomposition).
  bool AdvanceFrom(int segment, double start, double done, LocatorState& state,
                   EventHandler& handler);

 protected:
  bool Examine(int segment, double start, LocatorState& state, EventHandler& handler) override;

 private:
  // Advances state.z over [start, start + length] by the Taylor search.
  bool Search(int segment, double start, double length, LocatorState& state, EventHandler& handler);
  Eigen::MatrixXd taylor_;  // m x (kTaylorTerms + 1): A^k z / k!
};

// V1: the flagged sub-step [0, D] is walked on the dyadic grid of depth L = 34. From the current
// position (a multiple of D 2^-L) the largest aligned dyadic step inside the sub-step is tried; if
// its end is outside a wall (or the gap turned back near it), the step is halved until the
// crossing is bracketed to one cell; the event is placed at the cell's end and walking continues
// in the new state. Tables: 34 dense propagators per segment and state, straight from the
// balanced Pade (squaring up from the finest level would amplify rounding by 2^34); refused above
// 256 MiB.
class DyadicLocator final : public SubstepLocator {
 public:
  static constexpr EventMethod kMethod = EventMethod::kDyadic;
  static constexpr int kDyadicLevels = 34;
  DyadicLocator(const SegmentTables& tables, const SolverOptions& options);
  EventMethod method() const override { return kMethod; }

 protected:
  bool Examine(int segment, double start, LocatorState& state, EventHandler& handler) override;

 private:
  // levels_[segment][state][l] = expm(A D 2^-(l+1)), l = 0..kDyadicLevels-1.
  std::vector<std::array<std::vector<Eigen::MatrixXd>, 3>> levels_;
  Eigen::VectorXd zb_;
};

// V3: per whole segment, w = S^-1 z (one matvec); the gap of every wall is the closed form
// p(t) + sum e^{sigma t}(alpha cos wt + beta sin wt) + sum gamma e^{lambda t} (ClosedFormGap);
// its first rise is found with certified bounds and Newton. No event: z <- Phi z (the dense
// propagator) when the segment is entered unchanged, else S e^{B(h - t)} w. At an event
// z <- S e^{B t*} w and the search restarts in the new state. An ill-conditioned (segment, state)
// (cond(S) > spectral_max_condition) is handed to the Taylor search for the rest of the segment.
// Decompositions are built when their (segment, state) is first visited (a loaded run never
// decomposes its free and back states), so DoStep allocates only on a first visit.
class SpectralLocator final : public EventLocator {
 public:
  static constexpr EventMethod kMethod = EventMethod::kSpectral;
  SpectralLocator(const SegmentTables& tables, const SolverOptions& options);
  EventMethod method() const override { return kMethod; }
  bool DoStep(int segment, double start, LocatorState& state, EventHandler& handler) override;

 private:
  struct System {
    SpectralDecomposition decomposition;
    std::array<ClosedFormGap, kGapRows> gaps;  // indexed by GapWall::gap
    bool built = false;
    bool ok = false;
  };
  // The system of (segment, state), decomposed on first use.
  System& Prepared(int segment, ContactState state);
  double max_condition_;
  std::vector<std::array<System, 3>> systems_;  // [segment][state]
  std::vector<double> w_ref_;                   // per segment; 0 until its first visit
  TaylorLocator fallback_;
  Eigen::VectorXd w_, wt_, scratch_, z1_;
};

// The locator of `options.events`.
std::unique_ptr<EventLocator> MakeEventLocator(const SegmentTables& tables,
                                               const SolverOptions& options);

}  // namespace gearnvh
