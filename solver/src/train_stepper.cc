// The train stepper (train_stepper.h): set-up, the run loop, events and grid segments; the options'
// rules, the grid and the static state are in train_stepper_setup.cc.
#include "gearnvh/solver/train_stepper.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "gearnvh/solver/train_segment_runs.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_tangents.h"

namespace gearnvh {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// V1 and V2 never use a decomposition: their tuples are not decomposed.
TrainTableOptions CacheOptions(const TrainStepperOptions& options) {
  TrainTableOptions tables = options.tables;
  if (options.events != EventMethod::kSpectral)
    tables.decompose_after_visits = std::numeric_limits<int>::max();
  return tables;
}

// Whether sign * g stays within `tolerance` (the gap's rounding, TrainTables::GapTolerance) of
// where it starts, or below the wall, over [0, horizon]: a body resting on a wall or floating at
// the relative speed 0 moves its gap by rounding alone, and FirstRise would take that noise for
// crossings (a train without load chattered, 1000 events in one grid segment). A real crossing
// rises beyond the rounding; one that creeps slower is switched at a grid segment's start
// (SwitchOutside) as any start outside the wall.
bool WithinRounding(const ClosedFormGap& gap, double sign, double horizon, double tolerance) {
  const double start = std::min(sign * gap.StartValue(), 0.0);  // f(0), or 0 at or past the wall
  return start > -tolerance && start + gap.DerivativeBound(0.0, horizon, 1) * horizon <= tolerance;
}

}  // namespace

TrainStepper::TrainStepper(const TrainTables& tables, const TrainStepperOptions& options,
                           const Eigen::VectorXd& z0, const std::vector<ContactState>& states0)
    : t_(tables),
      options_(options),
      cache_(tables, CacheOptions(options)),
      grid_(tables),
      z_(z0),
      states_(states0) {
  options.Validate();
  const int m = tables.m;
  w_.resize(m);
  wt_.resize(m);
  scratch_.resize(m);
  zs_.resize(m);
  taylor_.resize(m, kTaylorTerms + 1);
  z1_.resize(m);
  if (options.events == EventMethod::kDyadic) {
    substep_map_.resize(m, m);
    dyadic_levels_.assign(kDyadicLevels, Eigen::MatrixXd(m, m));
  }
  roots_.resize(tables.meshes.size());
  root_walls_.resize(tables.meshes.size());
  key_.resize(static_cast<size_t>(cache_.KeyWords()));
  recenter_period_ = tables.common_period > 0.0 ? tables.common_period : tables.InputRevolution();
  next_recenter_ = recenter_period_;
  if (options.events == EventMethod::kSpectral && options.fusion_levels > 0) {
    fusion_ = std::make_unique<TrainSegmentRuns>(tables, options.fusion_levels,
                                                 options.fusion_limit_bytes,
                                                 options.max_cycle_map_segments, options.cancel);
  }
  for (const TrainMeshTable& mt : tables.meshes)
    period_cycles_.push_back(std::lround(tables.common_period / mt.period));
}

TrainStepper::~TrainStepper() = default;

void TrainStepper::Reset(const Eigen::VectorXd& z0, const std::vector<ContactState>& states0) {
  z_ = z0;
  states_ = states0;
  grid_ = TrainGrid(t_);
  time_ = 0.0;
  next_recenter_ = recenter_period_;
  events_at_period_ = 0;
  period_position_ = 0;
  segments_since_range_check_ = 0;
  if (fusion_) fusion_->ResetBackoff();
  summary_ = TrainStepperSummary{};
}

TrainStepperSummary TrainStepper::summary() const {
  TrainStepperSummary s = summary_;
  s.cache = cache_.summary();
  s.simulated_time = time_;
  JumpOutcome(s);
  FusionOutcome(s);
  return s;
}

bool TrainStepper::Run(double end_time, TrainRecorder* recorder) {
  while (time_ < end_time) {
    ThrowIfCancelled(options_.cancel);
    long advanced = FusedRun(end_time, recorder);  // grid segments
    if (advanced == 0) {
      const double until = std::min(end_time, grid_.end());
      if (!AdvanceGridSegment(until, recorder)) return false;
      if (until >= grid_.end()) {
        grid_.Next();
        advanced = 1;
      }
    }
    if (advanced > 0) {
      summary_.grid_segments += advanced;
      time_ = grid_.start();
      const bool period_start = AtPeriodStart();
      period_position_ = period_start ? 0 : period_position_ + advanced;
      if (period_start) TryJump(end_time, recorder);
      segments_since_range_check_ += advanced;
      if (segments_since_range_check_ >= kRangeCheckSegments) {
        segments_since_range_check_ = 0;
        if (!WithinRange()) return false;
      }
    }
    if (time_ >= next_recenter_) {
      Recenter();
      next_recenter_ += recenter_period_;
    }
  }
  return WithinRange();  // a run shorter than kRangeCheckSegments is checked too
}

bool TrainStepper::WithinRange() {
  for (int i = 0; i < static_cast<int>(t_.meshes.size()); ++i) {
    const TrainMeshTable& mt = t_.meshes[static_cast<size_t>(i)];
    if (mt.displacement_limit <= 0.0) continue;
    const int segment = grid_.segments()[static_cast<size_t>(i)];
    const double drive = std::abs(t_.GapValue(i, segment, true, z_));
    const double back = std::abs(t_.GapValue(i, segment, false, z_));
    if (drive <= mt.displacement_limit && back <= mt.displacement_limit) continue;  // not on NaN
    const double gap = std::isnan(drive) || std::isnan(back) ? drive + back : std::max(drive, back);
    summary_.info = TrainStepperSummary::Info::kOutOfRange;
    summary_.stopped_from = summary_.stopped_to = time_;
    summary_.stopped_on_mesh = mt.name;
    summary_.out_of_range_gap = gap;
    summary_.out_of_range_limit = mt.displacement_limit;
    summary_.out_of_range_twist = !mt.gear_mesh();
    return false;
  }
  return true;
}

void TrainStepper::Recenter() {
  const double drift = t_.recenter_row.dot(z_.head(t_.n));
  z_.head(t_.n) -= drift * t_.rigid_rotation;
  if (tangent_ != nullptr && tangent_->active()) tangent_->Recenter();
  ++summary_.recenterings;
}

int TrainStepper::Walls(int mesh, Wall walls[2]) const {
  switch (states_[static_cast<size_t>(mesh)]) {
    case ContactState::kDrive:
      walls[0] = {true, -1.0, ContactState::kFree};
      return 1;
    case ContactState::kBack:
      walls[0] = {false, 1.0, ContactState::kFree};
      return 1;
    case ContactState::kFree:
      walls[0] = {true, 1.0, ContactState::kDrive};
      walls[1] = {false, -1.0, ContactState::kBack};
      return 2;
  }
  return 0;
}

void TrainStepper::Switch(int mesh, ContactState to, double time, TrainRecorder* rec) {
  const size_t i = static_cast<size_t>(mesh);
  if (rec != nullptr) {
    // The rate of the wall's gap: the back flank's vector for a back contact or separation.
    const bool drive = to == ContactState::kDrive || states_[i] == ContactState::kDrive;
    const double rate = t_.meshes[i].Vector(drive).dot(z_.segment(t_.n, t_.n));
    rec->Event(mesh, states_[i], to, time, rate);
  }
  states_[i] = to;
  ++summary_.events;
  ++events_this_segment_;
  last_event_mesh_ = mesh;
}

void TrainStepper::Graze(int mesh, double time, TrainRecorder* rec) {
  ++summary_.grazing;
  ++events_this_segment_;
  last_event_mesh_ = mesh;
  if (rec != nullptr) rec->Grazing(mesh, time);
}

void TrainStepper::TaylorValue(double tau, Eigen::VectorXd& out) const {
  out = taylor_.col(kTaylorTerms);
  for (int k = kTaylorTerms - 1; k >= 0; --k) {
    out *= tau;
    out += taylor_.col(k);
  }
}

bool TrainStepper::SwitchOutside(TrainRecorder* rec) {
  for (int i = 0; i < static_cast<int>(t_.meshes.size()); ++i) {
    const int segment = grid_.segments()[static_cast<size_t>(i)];
    Wall walls[2];
    const int count = Walls(i, walls);
    for (int k = 0; k < count; ++k) {
      if (walls[k].sign * t_.GapValue(i, segment, walls[k].drive, z_) >
          t_.GapTolerance(i, segment, walls[k].drive, z_)) {
        Switch(i, walls[k].target, time_, rec);
        ++summary_.start_switches;
        return true;
      }
    }
  }
  return false;
}

void TrainStepper::Record(const TrainSystem& sys, const Eigen::Ref<const Eigen::VectorXd>& z_start,
                          double piece_start, double length, bool spectral, TrainRecorder* rec) {
  if (rec == nullptr) return;
  rec->Interval(piece_start, length, states_);
  rec->Piece(sys, z_start, piece_start, length, grid_.segments(), states_);
  // A sample on the piece's end belongs to the next piece (as the pair's ExactRecorder): a mesh
  // force steps there when the segment's stiffness does.
  const double sample_end = piece_start + length - 1e-9 * rec->sample_interval();
  while (rec->next_sample() < sample_end) {
    const double tau = std::max(0.0, rec->next_sample() - piece_start);
    if (spectral) {
      PropagateDecoupled(sys.decomposition, w_, tau, wt_, scratch_);
      zs_.noalias() = sys.decomposition.S * wt_;
    } else {
      TaylorValue(tau, zs_);
    }
    rec->Sample(rec->next_sample(), zs_, grid_.segments(), states_);
  }
}

bool TrainStepper::AdvanceGridSegment(double until, TrainRecorder* rec) {
  // The inputs: the manufacturing errors' means over the whole grid segment (independent of how
  // runs split) and the orders' states, exact where the state is (carried within the segment,
  // reset here so that rounding does not accumulate over a long run).
  const double h = grid_.end() - grid_.start();
  t_.SetInputs(grid_.cycles(), grid_.segments(), grid_.start(), h, z_);
  if (time_ != grid_.start()) t_.SetExcitation(time_, z_);
  events_this_segment_ = 0;
  // A state outside a wall at the grid segment's start (e_ij jumped) switches at once; at most
  // two switches per mesh (free -> contact -> never outside its own wall). Only at the start, as
  // the pair: right after a located event the gap is within the decomposition's rounding of the
  // wall, and re-testing it there could switch back and forth.
  if (time_ == grid_.start()) {
    for (size_t guard = 0; guard < 2 * t_.meshes.size() && SwitchOutside(rec); ++guard) {
    }
  }
  const TrainSystem* sys = nullptr;
  long entered_at = -1;  // the events count when `sys` was fetched: the tuple holds until the next
  while (until - time_ > 1e-15 * h) {
    if (sys == nullptr || entered_at != summary_.events) {
      sys = &cache_.Get(grid_.segments(), states_, key_);
      entered_at = summary_.events;
    }
    double step = 0.0;
    if (options_.events == EventMethod::kDyadic) {
      step = AdvanceDyadic(*sys, until - time_, rec);
    } else if (sys->spectral && options_.events == EventMethod::kSpectral) {
      step = AdvanceSpectral(*sys, until - time_, rec);
    } else {
      step = AdvanceDense(*sys, until - time_, rec);
    }
    time_ += step;
    if (events_this_segment_ > options_.max_events_per_segment) {
      summary_.info = TrainStepperSummary::Info::kTooManyEvents;
      summary_.stopped_from = grid_.start();
      summary_.stopped_to = grid_.end();
      summary_.event_limit = options_.max_events_per_segment;
      if (last_event_mesh_ >= 0)
        summary_.stopped_on_mesh = t_.meshes[static_cast<size_t>(last_event_mesh_)].name;
      return false;
    }
  }
  time_ = until;
  return true;
}

double TrainStepper::AdvanceSpectral(const TrainSystem& sys, double remaining, TrainRecorder* rec) {
  w_.noalias() = sys.decomposition.S_inv * z_;
  double best = -1.0;
  int best_mesh = -1;
  for (size_t i = 0; i < t_.meshes.size(); ++i) {
    roots_[i] = -1.0;
    const int segment = grid_.segments()[i];
    Wall walls[2];
    const int count = Walls(static_cast<int>(i), walls);
    const ClosedFormGap* held = nullptr;  // the closed form last loaded, and its wall
    double loaded = 0.0;
    for (int k = 0; k < count; ++k) {
      const double wall = t_.Wall(static_cast<int>(i), segment, walls[k].drive, z_);
      ClosedFormGap& gap = sys.Gap(i, walls[k].drive);
      if (&gap != held) {
        gap.Load(w_, -wall);
      } else {
        gap.ShiftConstant(loaded - wall);
      }
      held = &gap;
      loaded = wall;
      const double root =
          WithinRounding(gap, walls[k].sign, remaining,
                         t_.GapTolerance(static_cast<int>(i), segment, walls[k].drive, z_))
              ? -1.0
              : gap.FirstRise(walls[k].sign, remaining);
      if (root >= 0.0 && (roots_[i] < 0.0 || root < roots_[i])) {
        roots_[i] = root;
        root_walls_[i] = walls[k];
      }
    }
    if (roots_[i] >= 0.0 && (best < 0.0 || roots_[i] < best)) {
      best = roots_[i];
      best_mesh = static_cast<int>(i);
    }
  }
  const double step = best < 0.0 ? remaining : best;
  bool touch = false;
  double advance = step;
  if (best >= 0.0) {
    // Grazing: |g'| ~ 0 at the root and the gap curves back inside.
    const size_t i = static_cast<size_t>(best_mesh);
    const Wall& wall = root_walls_[i];
    // Rate and curvature do not depend on which wall's constant the closed form holds.
    const ClosedFormGap& gap = sys.Gap(i, wall.drive);
    touch = best > 0.0 && std::abs(gap.Rate(best)) <= options_.grazing_rate_tolerance &&
            wall.sign * gap.Curvature(best) < 0.0;
    if (touch) advance = std::min(remaining, best + 1e-12 * t_.longest_segment);
  }
  Record(sys, z_, time_, advance, true, rec);
  PropagateDecoupled(sys.decomposition, w_, advance, wt_, scratch_);
  z_.noalias() = sys.decomposition.S * wt_;
  const bool tangent = tangent_ != nullptr && tangent_->active();
  if (tangent) tangent_->PropagateDecoupled(sys.decomposition, advance);
  if (best < 0.0) return advance;
  if (touch) {
    Graze(best_mesh, time_ + best, rec);
    return advance;
  }
  // Simultaneous roots switch together, in the order of their roots.
  const double window = kSimultaneous * (grid_.end() - grid_.start()) + 4.0 * kEps * time_;
  int switched_now = 0;
  while (true) {
    int next = -1;
    for (size_t i = 0; i < roots_.size(); ++i) {
      if (roots_[i] >= 0.0 && roots_[i] <= best + window &&
          (next < 0 || roots_[i] < roots_[static_cast<size_t>(next)])) {
        next = static_cast<int>(i);
      }
    }
    if (next < 0) break;
    if (tangent) {
      const size_t i = static_cast<size_t>(next);
      tangent_->Saltation(next, grid_.segments()[i], states_[i], root_walls_[i].target, z_);
    }
    Switch(next, root_walls_[static_cast<size_t>(next)].target, time_ + advance, rec);
    roots_[static_cast<size_t>(next)] = -1.0;
    ++switched_now;
  }
  if (switched_now > 1) summary_.simultaneous_events += switched_now - 1;
  return advance;
}

}  // namespace gearnvh
