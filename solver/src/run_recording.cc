#include "gearnvh/solver/run_recording.h"

#include <algorithm>
#include <cstdint>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace gearnvh {
namespace {

// A long recorded run writes its samples into fresh memory, one first-touch page fault per 4 KiB
// (64 samples: two mesh cycles at 32 samples). Asking for transparent huge pages makes that one
// fault per 2 MiB, where the system allows it (THP "madvise" or "always"); only a hint, so a
// refusal changes nothing but the speed.
void PreferHugePages(const void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHugePage = uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<uintptr_t>(data);
  const uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const uintptr_t last = (begin + bytes) & ~(kHugePage - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

}  // namespace

RecordingReserve PlanRecording(const SolverOptions& options) {
  constexpr long kLoggedEventsPerCycle = 16;
  RecordingReserve r;
  if (options.record_trajectory) {
    r.samples =
        std::min(options.cycles * options.samples_per_cycle, options.max_trajectory_samples);
  }
  r.events = std::min(options.cycles * kLoggedEventsPerCycle, options.max_logged_events);
  return r;
}

RunRecording::RunRecording(const SegmentTables& tables, const SolverOptions& options,
                           size_t reserve_samples, size_t reserve_events)
    : tables_(tables), samples_per_cycle_(options.samples_per_cycle), cancel_(options.cancel) {
  trajectory_.samples.reserve(reserve_samples);
  PreferHugePages(trajectory_.samples.data(),
                  trajectory_.samples.capacity() * sizeof(TrajectorySample));
  trajectory_.events.reserve(reserve_events);
  if (options.record_trajectory) {
    recorder_.emplace(tables, options.samples_per_cycle, &trajectory_, options.cancel);
    piece_z_.resize(tables.m);
  }
}

bool RunRecording::StartRun(double time, bool record, ContactState contact) {
  if (record && contact == ContactState::kFree && free_since_ < 0.0) free_since_ = time;
  const bool recorded = record && recorder_.has_value();
  if (recorded && !window_started_) {
    recorder_->Start(time);
    window_started_ = true;
  }
  return recorded;
}

void RunRecording::BeginPiece(double time, const Eigen::VectorXd& z, ContactState contact) {
  piece_z_ = z;
  piece_start_ = time;
  piece_state_ = contact;
  piece_open_ = true;
}

void RunRecording::EndPiece(int segment, double time) {
  piece_open_ = false;
  recorder_->Piece(segment, piece_state_, piece_start_, time - piece_start_, piece_z_);
}

void RunRecording::Event(int segment, double time, ContactState from, ContactState to, double rate,
                         const Eigen::VectorXd& z, SolverSummary& summary) {
  if (piece_open_) {
    // z is the state at the event: the piece in the old state ends, one in the new state starts.
    EndPiece(segment, time);
    BeginPiece(time, z, to);
  }
  if (from == ContactState::kFree && free_since_ >= 0.0) summary.separated_s += time - free_since_;
  free_since_ = to == ContactState::kFree ? time : -1.0;
  ++summary.events;
  if (to == ContactState::kDrive)
    ++summary.drive_impacts;
  else if (to == ContactState::kBack)
    ++summary.back_impacts;
  else
    ++summary.separations;
  if (trajectory_.events.size() < trajectory_.events.capacity()) {
    trajectory_.events.push_back({time, from, to, rate});
  }
}

void RunRecording::UseCycleMap(const ConstantContactCycle* cycle) {
  if (cycle != cycle_map_) {
    rows_.reset();
    rows_refused_ = false;
  }
  cycle_map_ = cycle;
}

bool RunRecording::RowCycle(long cycle, double cycle_start, const Eigen::VectorXd& z) {
  if (!recorder_ || cycle_map_ == nullptr || rows_refused_) return false;
  if (!rows_) {
    rows_.emplace(tables_, *cycle_map_, *recorder_, samples_per_cycle_, cancel_);
    rows_refused_ = !rows_->usable();
    if (rows_refused_) return false;
  }
  if (!rows_->entered()) rows_->Enter(cycle, z);
  recorder_->RowCycle(*rows_, cycle, cycle_start, z);
  return true;
}

void RunRecording::Clear() {
  UseCycleMap(nullptr);
  trajectory_.samples.clear();
  trajectory_.events.clear();
  trajectory_.statistics = TrajectoryStatistics{};
  window_started_ = false;
  piece_open_ = false;
  free_since_ = -1.0;
}

}  // namespace gearnvh
