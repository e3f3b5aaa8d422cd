// What the stepping loop records on recorded cycles (docs/solver.md, Recording).
//   Pieces: the trajectory is handed to the ExactRecorder (exact_recorder.h) as pieces, each
//     starting at a segment start or an event with its state z, ending at the next event or the
//     segment end, propagated by the generator of one (segment, contact state).
//   Events: each contact change is counted (drive impacts, back impacts, separations) and logged
//     (time, from, to, gap rate) while the reserved log has room; beyond it, counted only.
//   Separated time: the recorded time in free flight, exact from the event times.
//   Row cycles: with a certified cycle map (UseCycleMap), a whole recorded cycle goes to the
//     recorder as output rows on its start state (cycle_output_rows.h, built on first use).
// Construction reserves every buffer; nothing here allocates afterwards except the output rows'
// tables, built once on the first row cycle.
#pragma once

#include <Eigen/Dense>
#include <cstddef>
#include <optional>

#include "gearnvh/solver/cycle_map.h"
#include "gearnvh/solver/cycle_output_rows.h"
#include "gearnvh/solver/exact_recorder.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/trajectory.h"

namespace gearnvh {

// What a run's recording reserves before it starts (SimulateExact; nothing grows during the
// run): uniform samples, samples_per_cycle per recorded cycle, at most max_trajectory_samples
// (none without record_trajectory), and the event log, 16 per recorded cycle, at most
// max_logged_events. The part of a run's memory that grows with SolverOptions::cycles.
struct RecordingReserve {
  long samples = 0;  // TrajectorySample slots
  long events = 0;   // EventRecord slots
  size_t sample_bytes() const { return static_cast<size_t>(samples) * sizeof(TrajectorySample); }
  size_t event_bytes() const { return static_cast<size_t>(events) * sizeof(EventRecord); }
  size_t bytes() const { return sample_bytes() + event_bytes(); }
};
RecordingReserve PlanRecording(const SolverOptions& options);

class RunRecording {
 public:
  // Reserves `reserve_samples` uniform samples and `reserve_events` logged events; the exact
  // recorder exists when options.record_trajectory.
  RunRecording(const SegmentTables& tables, const SolverOptions& options, size_t reserve_samples,
               size_t reserve_events);
  RunRecording(const RunRecording&) = delete;
  RunRecording& operator=(const RunRecording&) = delete;

  // A run of cycles starts at `time` in `contact`. Returns whether its pieces are recorded
  // (`record` and a recorder exists); starts the recorded window on the first such run.
  bool StartRun(double time, bool record, ContactState contact);
  void BeginPiece(double time, const Eigen::VectorXd& z, ContactState contact);
  void EndPiece(int segment, double time);
  // A contact change from `from` to `to` at `time` (z the state there) on a recorded cycle: an
  // open piece is split, the flight time, counts and log are updated.
  void Event(int segment, double time, ContactState from, ContactState to, double rate,
             const Eigen::VectorXd& z, SolverSummary& summary);
  // Recorded time in free flight up to `now`, including a flight still open.
  double SeparatedTime(const SolverSummary& summary, double now) const {
    return summary.separated_s + (free_since_ >= 0.0 ? now - free_since_ : 0.0);
  }
  // Certified permanent contact in cycle's state from now on (nullptr: none); not owned.
  void UseCycleMap(const ConstantContactCycle* cycle);
  // Records mesh cycle `cycle` (from `cycle_start`, state z at its start) by output rows; false
  // (nothing recorded) when there is no certified cycle map or its rows are not usable.
  bool RowCycle(long cycle, double cycle_start, const Eigen::VectorXd& z);
  // Forgets everything recorded (the buffers keep their capacity) and the cycle map.
  void Clear();
  Trajectory& trajectory() { return trajectory_; }
  size_t bytes() const {
    return (recorder_ ? recorder_->bytes() : 0) + (rows_ ? rows_->bytes() : 0);
  }

 private:
  const SegmentTables& tables_;
  int samples_per_cycle_;
  const std::atomic<bool>* cancel_;  // SolverOptions::cancel, for the output rows' build
  Trajectory trajectory_;
  std::optional<ExactRecorder> recorder_;
  const ConstantContactCycle* cycle_map_ = nullptr;
  std::optional<CycleOutputRows> rows_;
  bool rows_refused_ = false;
  bool window_started_ = false;
  double free_since_ = -1.0;  // start of the current recorded free flight, or -1
  bool piece_open_ = false;
  Eigen::VectorXd piece_z_;
  double piece_start_ = 0.0;
  ContactState piece_state_ = ContactState::kFree;
};

}  // namespace gearnvh
