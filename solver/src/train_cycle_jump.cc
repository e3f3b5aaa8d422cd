// Certified jumps of whole common periods in the train stepper (train_stepper.h,
// train_cycle_map.h).
#include <algorithm>
#include <cmath>
#include <limits>

#include "gearnvh/solver/train_cycle_map.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tangents.h"

namespace gearnvh {

void TrainGrid::Skip(const std::vector<long>& cycles_per_period, long long periods) {
  start_ = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < segment_.size(); ++i) {
    cycle_[i] += static_cast<long>(periods) * cycles_per_period[i];
    start_ = std::min(start_, static_cast<double>(cycle_[i]) * t_->meshes[i].period);
  }
  FindEnd();
}

bool TrainStepper::AtPeriodStart() const {
  if (t_.common_period <= 0.0) return false;
  const std::vector<int>& segments = grid_.segments();
  const std::vector<long>& cycles = grid_.cycles();
  for (size_t i = 0; i < segments.size(); ++i) {
    if (segments[i] != 0 || cycles[i] % period_cycles_[i] != 0) return false;
  }
  return true;
}

void TrainStepper::JumpOutcome(TrainStepperSummary& s) const {
  s.cycle_map_segments = period_segments_;
  s.cycle_map_bytes = cycle_map_ ? cycle_map_->bytes() : 0;
  if (s.jumps != TrainStepperSummary::Jumps::kNoConstantContact) return;
  if (!options_.jumps || options_.events != EventMethod::kSpectral) {
    s.jumps = TrainStepperSummary::Jumps::kDisabled;
  } else if (t_.common_period <= 0.0) {
    s.jumps = TrainStepperSummary::Jumps::kNoCommonPeriod;
  } else if (s.period_starts == 0) {
    s.jumps = TrainStepperSummary::Jumps::kTransientTooShort;
  }
}

void TrainStepper::TryJump(double end_time, const TrainRecorder* rec) {
  using Jumps = TrainStepperSummary::Jumps;
  Jumps& outcome = summary_.jumps;
  if (!options_.jumps || options_.events != EventMethod::kSpectral ||
      (tangent_ != nullptr && tangent_->active())) {
    outcome = Jumps::kDisabled;
    return;
  }
  if (outcome == Jumps::kPeriodTooLong) return;
  // Every contact held one state over the whole period just stepped, every gear mesh in contact
  // (a coupling's stage may be free: the map certifies its twist between both walls).
  const long events = summary_.events + summary_.grazing;
  const bool quiet = events == events_at_period_;
  events_at_period_ = events;
  bool contact = true;
  for (size_t i = 0; i < static_cast<size_t>(t_.gear_meshes); ++i)
    contact = contact && states_[i] != ContactState::kFree;
  const double horizon = rec != nullptr ? rec->start_time() : end_time;
  const double period = t_.common_period;
  const long long periods =
      std::min<long long>(static_cast<long long>(std::floor((horizon - time_) / period)),
                          (1LL << TrainCycleMap::kMaxJumpLog2) - 1);
  if (periods < options_.min_jump_periods) return;
  ++summary_.period_starts;
  if (!quiet || !contact) return;
  if (period_segments_ == 0)
    period_segments_ = CountCommonPeriodSegments(t_, options_.max_cycle_map_segments + 1);
  if (period_segments_ > options_.max_cycle_map_segments) {
    outcome = Jumps::kPeriodTooLong;
    return;
  }
  if (!cycle_map_ || cycle_map_->states() != states_) {
    cycle_map_ = std::make_unique<TrainCycleMap>(t_, states_, options_.jump_margin_fraction,
                                                 period_segments_, options_.cancel);
    ++summary_.cycle_map_builds;
  }
  summary_.cycle_map_info = cycle_map_->info();
  if (cycle_map_->info() != TrainCycleMap::Info::kSuccess) {
    if (outcome != Jumps::kJumped) outcome = Jumps::kMapRefused;
    return;
  }
  ++summary_.certificates;
  if (!cycle_map_->Certify(z_)) {
    if (outcome != Jumps::kJumped) outcome = Jumps::kNotCertified;
    return;
  }
  const double before = time_;
  cycle_map_->Jump(z_, periods);
  grid_.Skip(period_cycles_, periods);
  time_ = grid_.start();
  summary_.jumped_periods += periods;
  summary_.jumped_time += time_ - before;
  outcome = Jumps::kJumped;
  Recenter();
  next_recenter_ = time_ + recenter_period_;
}

}  // namespace gearnvh
