// Fusion in the stepping loop (docs/design.md §4.3, §4.5): the two ways a segment is advanced
// without looking for events, both with the very propagator products of step-by-step stepping.
//   Segment runs (SolverMethod::kFused, cycles not recorded, no tangent): from a segment start
//     the longest certified run of 2..2^fusion_levels aligned segments (segment_runs.h) advances
//     in one matvec, z_end = P z + sum_i U_i u_i (u_i the inputs of segment i); taken when the
//     certificate holds and the end state is inside every wall of the contact state. Refusals
//     back off: after k refusals in a row at a (state, segment) the next 2^k - 1 visits there
//     (at most kMaxBackoff) are not tried, so a strongly rattling run pays the certificate
//     rarely; one success resets it.
//   Whole segments: certified permanent contact (ConstantContactCycle, set by SimulateExact) or
//     the linear reference (ignore_walls): z <- Phi_{j,sigma} z, one matvec, no event possible.
// Nothing here allocates after construction.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <cstddef>
#include <vector>

#include "gearnvh/solver/event_locator.h"
#include "gearnvh/solver/segment_runs.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/tangent_propagator.h"

namespace gearnvh {

class SegmentFusion {
 public:
  SegmentFusion(const SegmentTables& tables, const SolverOptions& options);
  // Certified permanent contact: every segment in one matvec from now on.
  void SetPermanentContact(bool permanent) { permanent_ = permanent; }
  bool permanent_contact() const { return permanent_; }
  // Every segment is advanced whole (permanent contact or the linear reference).
  bool whole_segments() const { return permanent_ || ignore_walls_; }
  // Segment runs may be tried (built, walls active, contact not already certified).
  bool runs_enabled() const { return built_ && !permanent_ && !ignore_walls_; }
  // Visits skipped after a refusal at most (the back-off doubles up to this).
  static constexpr int kMaxBackoff = 63;
  // From the start of `segment` in mesh cycle `cycle`: advances state.z over a certified run and
  // returns its length in segments, or 0 (state unchanged) when no run is certified or the
  // (state, segment) is backing off. `locator` materialises a carried state first.
  int TryRun(long cycle, int segment, LocatorState& state, EventLocator& locator);
  // The whole segment in one matvec (and the tangent, if attached). Forced inline: at tier 1 the
  // call would be a tenth of the segment's cost.
  [[gnu::always_inline]] inline void AdvanceWhole(int segment, LocatorState& state) {
    const Eigen::MatrixXd& full = t_.systems[segment][static_cast<int>(state.contact)].full;
    end_.noalias() = full * state.z;
    state.z.swap(end_);
    if (state.tangent != nullptr) state.tangent->Propagate(full);
    ++state.matvecs;
  }
  size_t bytes() const;

 private:
  // TryRun without the back-off.
  int Advance(long cycle, int segment, LocatorState& state);
  const SegmentTables& t_;
  bool ignore_walls_;
  bool permanent_ = false;
  bool built_ = false;
  std::array<SegmentRunTable, 3> runs_;  // per contact state
  // Per (state, segment): visits still to skip, and the current back-off length.
  std::vector<int> skip_, backoff_;
  Eigen::VectorXd start_, end_, certify_scratch_, inputs_;
  SegmentTables::CyclePhase phase_;  // the excitation's phases of the current cycle
};

}  // namespace gearnvh
