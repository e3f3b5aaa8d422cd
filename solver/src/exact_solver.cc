#include "gearnvh/solver/exact_solver.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/cycle_map.h"
#include "gearnvh/solver/spectral_locator.h"

namespace gearnvh {

void SolverOptions::Validate() const {
  if (cycles < 1)
    throw InputError("SolverOptions.cycles", 0, std::to_string(cycles), "must be >= 1");
  if (transient_cycles < 0) {
    throw InputError("SolverOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (max_events_per_cycle < 1) {
    throw InputError("SolverOptions.max_events_per_cycle", 0, std::to_string(max_events_per_cycle),
                     "must be >= 1");
  }
  if (max_trajectory_samples < 0 || max_logged_events < 0) {
    throw InputError("SolverOptions.max_trajectory_samples", 0, "", "memory bounds must be >= 0");
  }
  if (!(spectral_max_condition >= 1.0)) {
    throw InputError("SolverOptions.spectral_max_condition", 0,
                     std::to_string(spectral_max_condition), "must be >= 1");
  }
  if (!(carry_max_error >= 0.0)) {
    throw InputError("SolverOptions.carry_max_error", 0, std::to_string(carry_max_error),
                     "must be >= 0");
  }
  if (fusion_levels < 0 || fusion_levels > 5) {
    throw InputError("SolverOptions.fusion_levels", 0, std::to_string(fusion_levels),
                     "must be in [0, 5] (runs of up to 32 segments)");
  }
  if (samples_per_cycle < 1) {
    throw InputError("SolverOptions.samples_per_cycle", 0, std::to_string(samples_per_cycle),
                     "must be >= 1");
  }
  if (!(grazing_rate_tolerance >= 0.0)) {
    throw InputError("SolverOptions.grazing_rate_tolerance", 0,
                     std::to_string(grazing_rate_tolerance), "must be >= 0");
  }
}

const char* EventMethodName(EventMethod m) {
  switch (m) {
    case EventMethod::kDyadic:
      return "v1";
    case EventMethod::kTaylor:
      return "v2";
    case EventMethod::kSpectral:
      return "v3";
  }
  return "unknown";
}

const char* LadderMethodName(LadderMethod m) {
  switch (m) {
    case LadderMethod::kV1:
      return "v1";
    case LadderMethod::kV2:
      return "v2";
    case LadderMethod::kV3:
      return "v3";
    case LadderMethod::kFused:
      return "fused";
  }
  return "unknown";
}

EventMethod EventMethodOf(LadderMethod m) {
  switch (m) {
    case LadderMethod::kV1:
      return EventMethod::kDyadic;
    case LadderMethod::kV2:
      return EventMethod::kTaylor;
    case LadderMethod::kV3:
    case LadderMethod::kFused:
      return EventMethod::kSpectral;
  }
  return EventMethod::kSpectral;
}

void ApplyLadderMethod(LadderMethod m, SolverOptions& options) {
  options.events = EventMethodOf(m);
  options.method = m == LadderMethod::kFused ? SolverMethod::kFused : SolverMethod::kStepped;
}

const char* SolverMethodName(SolverMethod m) {
  return m == SolverMethod::kFused ? "fused" : "stepped";
}

const char* SolverStatusName(SolverStatus s) {
  switch (s) {
    case SolverStatus::kSuccess:
      return "success";
    case SolverStatus::kTooManyEvents:
      return "too_many_events";
    case SolverStatus::kOutOfRange:
      return "out_of_range";
  }
  return "?";
}

std::string OutOfRangeMessage(const std::string& where, double time, double gap, double limit) {
  std::ostringstream os;
  os.precision(4);
  os << where << " (t = " << time << " s) a flank gap reached " << 1e3 * gap
     << " mm, past the teeth's whole depth beyond a wall (" << 1e3 * limit
     << " mm): the response grows without bound at this operating point and tier, and the model "
        "no longer describes the gears; the run stopped there";
  return os.str();
}

ExactStepper::ExactStepper(const SegmentTables& tables, const SolverOptions& options,
                           const Eigen::VectorXd& z0, ContactState state0, size_t reserve_samples,
                           size_t reserve_events)
    : t_(tables),
      options_(options),
      locator_(MakeEventLocator(tables, options)),
      tangent_(tables),
      fusion_(tables, options),
      recording_(tables, options, reserve_samples, reserve_events) {
  state_.z = z0;
  state_.contact = state0;
  phase_ = tables.MakeCyclePhase();
  UpdateTableStatistics();
}

void ExactStepper::UpdateTableStatistics() {
  const LocatorStatistics& located = locator_->statistics();
  summary_.spectral_fallback_systems = located.spectral_fallback_systems;
  summary_.spectral_max_condition = located.spectral_max_condition;
  summary_.carried_systems = located.carried_systems;
  summary_.carry_error_bound = located.carry_error_bound;
  summary_.table_bytes =
      located.table_bytes + fusion_.bytes() + t_.TableBytes() + recording_.bytes();
}

bool ExactStepper::Run(long cycles, bool record) {
  record_ = record;
  const double run_start = static_cast<double>(cycle_) * t_.mesh_period;
  const bool recorded = recording_.StartRun(run_start, record, state_.contact);
  const bool try_runs = fusion_.runs_enabled() && !tangent_.active() && !recorded;
  // Between segments only the input slots of z are touched unless a piece is recorded or a
  // tangent is carried: the locator may then keep the state in its own coordinates.
  state_.allow_carry = !recorded && !tangent_.active();
  bool ok = true;
  for (long c = 0; c < cycles; ++c, ++cycle_) {
    ThrowIfCancelled(options_.cancel);
    events_this_cycle_ = 0;
    if (!StepCycle(recorded, try_runs)) {
      ok = TooManyEvents();
      break;
    }
    EndCycle(record);
    if (!WithinRange()) {
      ok = false;
      break;
    }
  }
  UpdateTableStatistics();  // the locator builds tables on first visits
  return ok;
}

void ExactStepper::SetCycleMap(const ConstantContactCycle* cycle) {
  cycle_map_ = cycle;
  recording_.UseCycleMap(cycle);
  if (cycle != nullptr) cycle_end_.resize(t_.m);
}

void ExactStepper::StepWholeSegments(bool recorded) {
  // Certified permanent contact or the linear reference: no wall can be reached.
  const double cycle_start = static_cast<double>(cycle_) * t_.mesh_period;
  if (cycle_map_ != nullptr && !tangent_.active()) {
    t_.SetInputs(cycle_, 0, state_.z, phase_);
    if (!recorded || recording_.RowCycle(cycle_, cycle_start, state_.z)) {
      cycle_end_.noalias() = cycle_map_->map() * state_.z;
      state_.z.swap(cycle_end_);
      ++state_.matvecs;
      const int last = t_.segments() - 1;
      time_ = cycle_start + t_.boundaries[last] + t_.SegmentLength(last);
      return;
    }
  }
  for (int j = 0; j < t_.segments(); ++j) {
    const double seg_start = cycle_start + t_.boundaries[j];
    t_.SetInputs(cycle_, j, state_.z, phase_);
    if (recorded) recording_.BeginPiece(seg_start, state_.z, state_.contact);
    fusion_.AdvanceWhole(j, state_);
    time_ = seg_start + t_.SegmentLength(j);
    if (recorded) recording_.EndPiece(j, time_);
  }
}

bool ExactStepper::StepCycle(bool recorded, bool try_runs) {
  if (fusion_.whole_segments()) {
    StepWholeSegments(recorded);
    return true;
  }
  // Dispatched once per cycle to the final locator class: the per-segment call is direct (and the
  // sub-step loop of V1/V2 inlined), as it was before the locators were split out.
  switch (locator_->method()) {
    case EventMethod::kSpectral:
      return StepCycleWith(static_cast<SpectralLocator&>(*locator_), recorded, try_runs);
    case EventMethod::kTaylor:
      return StepCycleWith(static_cast<TaylorLocator&>(*locator_), recorded, try_runs);
    case EventMethod::kDyadic:
      return StepCycleWith(static_cast<DyadicLocator&>(*locator_), recorded, try_runs);
  }
  return StepCycleWith(*locator_, recorded, try_runs);
}

template <class Locator>
bool ExactStepper::StepCycleWith(Locator& locator, bool recorded, bool try_runs) {
  const double cycle_start = static_cast<double>(cycle_) * t_.mesh_period;
  for (int j = 0; j < t_.segments(); ++j) {
    // V3 carrying (never while recording or with a tangent): the segments the screen clears are
    // stepped inside the locator, without the per-segment bookkeeping below.
    if constexpr (requires { locator.CarryThrough(j, cycle_, phase_, state_); }) {
      if (state_.z_stale && !try_runs) {
        j = locator.CarryThrough(j, cycle_, phase_, state_);
        if (j == t_.segments()) {
          time_ = cycle_start + t_.boundaries[j - 1] + t_.SegmentLength(j - 1);
          break;
        }
      }
    }
    if (try_runs) {
      const int run = fusion_.TryRun(cycle_, j, state_, locator);
      if (run > 0) {
        summary_.run_fused_segments += run;
        j += run - 1;
        time_ = cycle_start + t_.boundaries[j + 1];
        continue;
      }
    }
    const double seg_start = cycle_start + t_.boundaries[j];
    t_.SetInputs(cycle_, j, state_.z, phase_);
    if (recorded) recording_.BeginPiece(seg_start, state_.z, state_.contact);
    if (!locator.DoStep(j, seg_start, state_, *this)) return false;
    time_ = seg_start + t_.SegmentLength(j);
    if (recorded) recording_.EndPiece(j, time_);
  }
  return true;
}

void ExactStepper::EndCycle(bool record) {
  ++summary_.mesh_cycles;
  if (fusion_.permanent_contact()) ++summary_.fused_cycles;
  if (record) {
    summary_.recorded_s += t_.mesh_period;
    ++summary_.recorded_cycles;
  }
  // Remove the drift of the pair's free rotation (exactly invariant; see SegmentTables).
  const double drift = t_.recenter_row.dot(state_.z.head(t_.n));
  state_.z.head(t_.n) -= drift * t_.rigid_rotation;
  if (tangent_.active()) tangent_.EndCycle();
}

bool ExactStepper::Switch(int segment, const SegmentSystem& from_system, const GapWall& wall,
                          double time, bool state_triggered) {
  const double rate = wall.rate->dot(state_.z);
  const ContactState from = state_.contact;
  state_.contact = wall.target;
  ++events_this_cycle_;
  if (state_triggered) {
    summary_.min_event_rate = std::min(summary_.min_event_rate, std::abs(rate));
    if (tangent_.active()) {
      const SegmentSystem& to = t_.systems[segment][static_cast<int>(wall.target)];
      tangent_.Saltation(from_system.A, to.A, *wall.row, state_.z);
    }
  }
  if (record_) recording_.Event(segment, time, from, wall.target, rate, state_.z, summary_);
  return events_this_cycle_ <= options_.max_events_per_cycle;
}

bool ExactStepper::Graze(double /*time*/) {
  ++summary_.grazing;
  return ++events_this_cycle_ <= options_.max_events_per_cycle;
}

void ExactStepper::AttachTangent(Eigen::MatrixXd* tangent) {
  tangent_.Attach(tangent);
  state_.tangent = tangent != nullptr ? &tangent_ : nullptr;
}

void ExactStepper::Restart(const Eigen::VectorXd& z, ContactState state) {
  state_.z = z;
  state_.z_stale = false;
  state_.contact = state;
  state_.matvecs = 0;
  cycle_ = 0;
  time_ = 0.0;
  events_this_cycle_ = 0;
  fusion_.SetPermanentContact(false);
  cycle_map_ = nullptr;
  SolverSummary fresh;
  fresh.table_bytes = summary_.table_bytes;
  fresh.spectral_fallback_systems = summary_.spectral_fallback_systems;
  fresh.spectral_max_condition = summary_.spectral_max_condition;
  fresh.carried_systems = summary_.carried_systems;
  fresh.carry_error_bound = summary_.carry_error_bound;
  summary_ = fresh;
  recording_.Clear();
}

bool ExactStepper::TooManyEvents() {
  summary_.status = SolverStatus::kTooManyEvents;
  summary_.message = "more than " + std::to_string(options_.max_events_per_cycle) +
                     " contact events in mesh cycle " + std::to_string(cycle_);
  return false;
}

bool ExactStepper::WithinRange() {
  if (t_.displacement_limit <= 0.0) return true;
  const SegmentSystem& s = t_.systems[0][static_cast<int>(ContactState::kFree)];
  const double drive = std::abs(s.gap_drive.dot(state_.z)),
               back = std::abs(s.gap_back.dot(state_.z));
  if (drive <= t_.displacement_limit && back <= t_.displacement_limit) return true;  // not on NaN
  const double gap = std::isnan(drive) || std::isnan(back) ? drive + back : std::max(drive, back);
  summary_.status = SolverStatus::kOutOfRange;
  summary_.message = OutOfRangeMessage("at mesh cycle " + std::to_string(cycle_), time_, gap,
                                       t_.displacement_limit);
  return false;
}

void ExactStepper::JumpTo(const Eigen::VectorXd& z, long cycles) {
  state_.z = z;
  cycle_ += cycles;
  time_ = static_cast<double>(cycle_) * t_.mesh_period;
  summary_.mesh_cycles += cycles;
  summary_.jumped_cycles += cycles;
}

std::pair<Eigen::VectorXd, ContactState> StaticInitialState(const SegmentTables& t) {
  Eigen::VectorXd z = DriveEquilibrium(t);
  const SegmentSystem& drive = t.systems[0][static_cast<int>(ContactState::kDrive)];
  if (drive.gap_drive.dot(z) > 0.0) return {z, ContactState::kDrive};
  z.head(t.n).setZero();
  return {z, ContactState::kFree};
}

Eigen::VectorXd DriveEquilibrium(const SegmentTables& t) {
  const int n = t.n, m = t.m;
  const SegmentSystem& drive = t.systems[0][static_cast<int>(ContactState::kDrive)];
  // K x = f has the pair's free rotation as a null direction (and, with friction, a small
  // inconsistency along it): solve in the least-squares sense together with r~^T x = 0, which
  // makes the stacked system full rank and the solution centred (no large rigid angles).
  Eigen::MatrixXd B(n + 1, n);
  B.topRows(n) = -drive.A.block(n, 0, n, n);  // M^-1 K
  const double scale = B.topRows(n).norm() / std::max(t.recenter_row.norm(), 1e-300);
  B.row(n) = scale * t.recenter_row;
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
  rhs.head(n) = drive.A.block(n, 2 * n, n, 1);  // M^-1 f
  Eigen::VectorXd z = Eigen::VectorXd::Zero(m);
  z[2 * n] = 1.0;
  z.head(n) = B.colPivHouseholderQr().solve(rhs);
  return z;
}

SolverResult SimulateExact(const SegmentTables& tables, const Eigen::VectorXd& z0,
                           ContactState state0, const SolverOptions& options,
                           const ProgressCallback& progress) {
  options.Validate();
  const auto start = std::chrono::steady_clock::now();
  const long wanted_samples =
      options.record_trajectory ? options.cycles * options.samples_per_cycle : 0;
  const RecordingReserve reserve = PlanRecording(options);
  ExactStepper stepper(tables, options, z0, state0, static_cast<size_t>(reserve.samples),
                       static_cast<size_t>(reserve.events));
  bool ok = true;
  // Fusion needs contact without excitation or manufacturing errors (both make one mesh cycle's
  // map differ from the next's); the certificate is retried after every chunk of
  // stepped cycles (the transient decays), and once it holds the rest of the transient is jumped.
  std::optional<ConstantContactCycle> cycle;
  const bool may_fuse = options.method == SolverMethod::kFused && tables.excitation.empty() &&
                        !tables.errors.active();
  auto try_fuse = [&]() {
    const ContactState state = stepper.contact();
    if (!may_fuse || stepper.summary().contact_certified || state == ContactState::kFree) return;
    if (!cycle || cycle->state() != state) cycle.emplace(tables, state, options.cancel);
    if (!cycle->Certify(stepper.state()).certified) return;
    stepper.summary().contact_certified = true;
    stepper.SetFusedContact(true);
    if (options.cycle_rows) stepper.SetCycleMap(&*cycle);
    const long remaining_transient = options.transient_cycles - stepper.summary().mesh_cycles;
    if (remaining_transient > 0) {
      stepper.JumpTo(cycle->Jump(stepper.state(), remaining_transient), remaining_transient);
    }
  };
  try_fuse();
  // Run in ~100 chunks so a caller can show progress.
  const long total = options.transient_cycles + options.cycles;
  const long chunk = std::max<long>(1, total / 100);
  for (long done = stepper.summary().mesh_cycles; done < total && ok;) {
    const bool record = done >= options.transient_cycles;
    const long n =
        record ? std::min(chunk, total - done) : std::min(chunk, options.transient_cycles - done);
    ok = stepper.Run(n, record);
    if (ok) try_fuse();
    done = stepper.summary().mesh_cycles;
    if (progress) progress(done, total);
  }
  SolverResult result;
  result.summary = stepper.summary();
  SolverSummary& s = result.summary;
  s.separated_s = stepper.SeparatedTime();
  s.trajectory_truncated = wanted_samples > options.max_trajectory_samples ||
                           s.events > static_cast<long>(stepper.trajectory().events.capacity());
  s.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  s.simulated_s = stepper.time();
  s.real_time_ratio = s.wall_s > 0.0 ? s.simulated_s / s.wall_s : 0.0;
  // Events are counted in recorded cycles: per the cycles recorded (fewer when the run stopped).
  s.events_per_cycle =
      static_cast<double>(s.events) / static_cast<double>(std::max<long>(s.recorded_cycles, 1));
  s.matvec_per_cycle =
      static_cast<double>(s.matvecs) / static_cast<double>(std::max<long>(s.mesh_cycles, 1));
  result.trajectory = std::move(stepper.trajectory());
  result.final_state = stepper.state();
  result.final_contact = stepper.contact();
  return result;
}

}  // namespace gearnvh
