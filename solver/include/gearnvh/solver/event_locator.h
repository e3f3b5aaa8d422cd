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
//   SpectralLocator (V3, default; spectral_locator.h): closed-form gap in the decoupled
//     coordinates of the generator per whole segment (spectral_gap.h), exact to rounding, two
//     matvecs without an event. An ill-conditioned (segment, state) falls back to the
//     TaylorLocator's search.
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
// DoStep does not allocate: each locator owns its tables and workspace. The classes are final,
// and ExactStepper dispatches once per mesh cycle to the concrete class, so the per-segment call
// is direct (the V1/V2 sub-step loop is inline); at tier 1 a segment costs only ~100 ns.
//
// Gear trains (how solver/train_* can adopt this interface): the searches never name a flank.
// They loop over the GapWalls of the current state (row, rate row, trigger sign, target, index
// into the gap set), take the earliest root over all of them, and hand it to the handler; the
// V3 tables hold one ClosedFormGap per gap row, indexed by GapWall::gap. Only two lookups tie a
// locator to a single pair: the generator t_.systems[j][sigma] and ActiveWalls(sys, sigma). A
// train stepper replaces them by its (segment, contact combination) systems and by the walls of
// every mesh (each wall's target then names that mesh's new state, and its handler updates the
// combination); the search loops, the sub-step screen, the tolerance rules and the handler
// protocol carry over unchanged.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <vector>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

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
// Inline: it is called on every sub-step.
inline int ActiveWalls(const SegmentSystem& sys, ContactState state, GapWall out[kMaxWalls]) {
  switch (state) {
    case ContactState::kFree:
      out[0] = {&sys.gap_drive, &sys.gap_drive_rate, 1.0, ContactState::kDrive, 0};
      out[1] = {&sys.gap_back, &sys.gap_back_rate, -1.0, ContactState::kBack, 1};
      return 2;
    case ContactState::kDrive:
      out[0] = {&sys.gap_drive, &sys.gap_drive_rate, -1.0, ContactState::kFree, 0};
      return 1;
    case ContactState::kBack:
      out[0] = {&sys.gap_back, &sys.gap_back_rate, 1.0, ContactState::kFree, 1};
      return 1;
  }
  return 0;
}
// The gap set of a pair: 0 -> g+ (drive flank), 1 -> g- (back flank).
inline const Eigen::RowVectorXd& GapRow(const SegmentSystem& sys, int gap) {
  return gap == 0 ? sys.gap_drive : sys.gap_back;
}

// What a locator advances: the augmented state, its contact state, the tangent (null when none is
// attached; advanced by the same maps) and the running matvec count.
struct LocatorState {
  Eigen::VectorXd z;
  ContactState contact = ContactState::kFree;
  TangentPropagator* tangent = nullptr;
  long matvecs = 0;
  // Set by the stepper: between two segments of one mesh cycle nothing but the input slots of z
  // is read or written, so a locator may carry the state in its own coordinates (V3: decoupled)
  // instead of z. Never across a cycle end, a recorded piece or an attached tangent.
  bool allow_carry = false;
  // Set by the locator while it carries: z holds valid input slots only, the rest is stale until
  // EventLocator::Materialise(state).
  bool z_stale = false;
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
  // V3 carried steps (SpectralLocator): (segment, state) pairs stepped in decoupled coordinates,
  // and the largest first-order bound of the relative state error one carried step adds,
  // (m + 1) eps |S_{j+1}|_1 |C_j|_1 |S_j^-1|_1 (C_j the carry matrix).
  int carried_systems = 0;
  double carry_error_bound = 0.0;
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
  // Writes the carried state back into state.z (all but the input slots) and clears z_stale.
  // Only a locator that sets z_stale carries; the others never need it.
  virtual void Materialise(LocatorState& state) { state.z_stale = false; }
  const LocatorStatistics& statistics() const { return statistics_; }

 protected:
  // Rounding floor of the gap `row` . z (its terms can be much larger than the gap, e.g. as the
  // pair's free rotation drifts): inside it a state is not moved.
  double WallTolerance(const Eigen::RowVectorXd& row, const Eigen::VectorXd& z) const {
    double magnitude = 0.0;
    for (Eigen::Index i = 0; i < row.size(); ++i) magnitude += std::abs(row[i] * z[i]);
    return gap_tolerance_ + 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
  }
  // gap > WallTolerance(row, z), skipping the sum when gap is below its floor gap_tolerance_.
  bool BeyondTolerance(double gap, const Eigen::RowVectorXd& row, const Eigen::VectorXd& z) const {
    return gap > gap_tolerance_ && gap > WallTolerance(row, z);
  }
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
  // SolverOptions::cancel: polled where a locator builds tables (per segment or system built).
  const std::atomic<bool>* cancel_;
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

// Inline: called at every segment start (V3) or flagged sub-step (V1).
inline int EventLocator::Outside(const SegmentSystem& sys, ContactState state,
                                 const Eigen::VectorXd& z, bool with_tolerance) const {
  GapWall walls[kMaxWalls];
  const int count = ActiveWalls(sys, state, walls);
  for (int i = 0; i < count; ++i) {
    const double gap = walls[i].sign * walls[i].row->dot(z);
    if (with_tolerance ? BeyondTolerance(gap, *walls[i].row, z) : gap > 0.0) return i;
  }
  return -1;
}

inline bool EventLocator::SwitchIfOutsideAtStart(int segment, double start, LocatorState& state,
                                                 EventHandler& handler) const {
  // At most two switches: free -> contact, and a contact state can never be outside its own wall
  // right after entering it.
  for (int guard = 0; guard < 2; ++guard) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    const int outside = Outside(sys, state.contact, state.z, true);
    if (outside < 0) return true;
    GapWall walls[kMaxWalls];
    ActiveWalls(sys, state.contact, walls);
    if (!handler.Switch(segment, sys, walls[outside], start, /*state_triggered=*/false)) {
      return false;
    }
  }
  return true;
}

// Inline: the sub-step loop is the hot path of V1/V2 (tier 1 costs tens of ns per sub-step).
inline bool SubstepLocator::PossibleEvent(const SegmentSystem& sys, const LocatorState& state,
                                          bool segment_start) const {
  GapWall walls[kMaxWalls];
  const int count = ActiveWalls(sys, state.contact, walls);
  for (int i = 0; i < count; ++i) {
    const GapWall& w = walls[i];
    // The gap rows change at a segment boundary (e_j): the start itself may be outside.
    if (segment_start && BeyondTolerance(w.sign * w.row->dot(state.z), *w.row, state.z)) {
      return true;
    }
    if (w.sign * w.row->dot(z1_) > 0.0) return true;  // crossed by the end of the sub-step
    // Turned towards the wall and back inside the sub-step: an interior extremum to examine.
    if (w.sign * w.rate->dot(state.z) > 0.0 && w.sign * w.rate->dot(z1_) < 0.0) return true;
  }
  return false;
}

inline bool SubstepLocator::DoStep(int segment, double start, LocatorState& state,
                                   EventHandler& handler) {
  const int n = t_.substeps[segment];
  const double d = t_.SegmentLength(segment) / n;
  for (int i = 0; i < n; ++i) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(state.contact)];
    z1_.noalias() = sys.substep * state.z;
    ++state.matvecs;
    if (!PossibleEvent(sys, state, i == 0)) {
      state.z.swap(z1_);
      if (state.tangent != nullptr) state.tangent->Propagate(sys.substep);
    } else if (!Examine(segment, start + i * d, state, handler)) {
      return false;
    }
  }
  return true;
}

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

// The locator of `options.events`.
std::unique_ptr<EventLocator> MakeEventLocator(const SegmentTables& tables,
                                               const SolverOptions& options);

}  // namespace gearnvh
