#include "gearnvh/solver/exact_solver.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "bracketed_newton.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/cycle_map.h"

namespace gearnvh {

void SolverOptions::Validate() const {
  if (cycles < 1) throw InputError("analysis.cycles", 0, std::to_string(cycles), "must be >= 1");
  if (transient_cycles < 0) {
    throw InputError("analysis.transient_cycles", 0, std::to_string(transient_cycles),
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

void ApplyMethodName(const std::string& name, SolverOptions& options, const std::string& field) {
  options.method = SolverMethod::kStepped;
  if (name == "v1") {
    options.events = EventMethod::kDyadic;
  } else if (name == "v2") {
    options.events = EventMethod::kTaylor;
  } else if (name == "v3") {
    options.events = EventMethod::kSpectral;
  } else if (name == "fused") {
    options.events = EventMethod::kSpectral;
    options.method = SolverMethod::kFused;
  } else {
    throw InputError(field, 0, name, "must be one of v1, v2, v3, fused");
  }
}

const char* SolverMethodName(SolverMethod m) {
  return m == SolverMethod::kFused ? "fused" : "stepped";
}

const char* SolverStatusName(SolverStatus s) {
  return s == SolverStatus::kSuccess ? "success" : "too_many_events";
}

namespace {

// A wall that can be reached in a state: the event happens when sign * (row . z) rises above 0.
struct Wall {
  const Eigen::RowVectorXd* row;
  double sign;
  ContactState target;
};

int Walls(const SegmentSystem& sys, ContactState state, Wall out[2]) {
  switch (state) {
    case ContactState::kFree:
      out[0] = {&sys.gap_drive, 1.0, ContactState::kDrive};
      out[1] = {&sys.gap_back, -1.0, ContactState::kBack};
      return 2;
    case ContactState::kDrive:
      out[0] = {&sys.gap_drive, -1.0, ContactState::kFree};
      return 1;
    case ContactState::kBack:
      out[0] = {&sys.gap_back, 1.0, ContactState::kFree};
      return 1;
  }
  return 0;
}

const Eigen::RowVectorXd& RateRow(const SegmentSystem& sys, const Eigen::RowVectorXd* row) {
  return row == &sys.gap_drive ? sys.gap_drive_rate : sys.gap_back_rate;
}

// p(tau) = sum_k c_k tau^k and its derivative (Horner).
inline double Poly(const double* c, int degree, double tau) {
  double v = c[degree];
  for (int k = degree - 1; k >= 0; --k) v = v * tau + c[k];
  return v;
}
inline double PolyDerivative(const double* c, int degree, double tau) {
  double v = degree * c[degree];
  for (int k = degree - 1; k >= 1; --k) v = v * tau + k * c[k];
  return v;
}

// Safeguarded Newton on [lo, hi] from the midpoint, to rounding of `scale`.
template <typename F, typename DF>
double Bracketed(F&& f, DF&& df, double lo, double hi, double scale) {
  return BracketedNewton(f, df, lo, hi, 0.5 * (lo + hi), 1e-16 * scale);
}

// First tau in (0, length] where p rises above 0, or -1. p(0) <= 0 is assumed (we start inside).
// The interval is sampled; where no sample is outside, every local maximum between samples
// (p' changing from + to -) is located by Newton on p' and tested, so a brief excursion across
// the wall between samples is not missed.
double FirstRoot(const double* c, int degree, double length, int samples) {
  auto p = [&](double t) { return Poly(c, degree, t); };
  auto dp = [&](double t) { return PolyDerivative(c, degree, t); };
  auto ddp = [&](double t) {
    double v = degree * (degree - 1) * c[degree];
    for (int k = degree - 1; k >= 2; --k) v = v * t + k * (k - 1) * c[k];
    return v;
  };
  double a = 0.0, slope_a = dp(0.0);
  for (int i = 1; i <= samples; ++i) {
    const double b = length * i / samples;
    if (p(b) > 0.0) return Bracketed(p, dp, a, b, length);
    const double slope_b = dp(b);
    if (slope_a > 0.0 && slope_b < 0.0) {
      // A maximum inside (a, b): find it (root of -p'), and if it is outside the wall, the first
      // crossing lies between a and the maximum.
      const double peak = Bracketed([&](double t) { return -dp(t); },
                                    [&](double t) { return -ddp(t); }, a, b, length);
      if (p(peak) > 0.0) return Bracketed(p, dp, a, peak, length);
    }
    a = b;
    slope_a = slope_b;
  }
  return -1.0;
}

}  // namespace

ExactStepper::ExactStepper(const SegmentTables& tables, const SolverOptions& options,
                           const Eigen::VectorXd& z0, ContactState state0, size_t reserve_samples,
                           size_t reserve_events)
    : t_(tables),
      options_(options),
      z_(z0),
      z1_(z0.size()),
      taylor_(z0.size(), kTaylorTerms + 1),
      contact_(state0),
      gap_tolerance_(1e-12 * tables.half_backlash) {
  za_.resize(z0.size());
  zb_.resize(z0.size());
  if (options.events == EventMethod::kDyadic) {
    const double bytes = static_cast<double>(tables.segments()) * 3 * kDyadicLevels *
                         static_cast<double>(tables.m) * tables.m * sizeof(double);
    if (bytes > 256.0 * 1024 * 1024) {
      throw InputError("event method", 0, "v1",
                       "needs " + std::to_string(static_cast<long>(bytes / 1048576)) +
                           " MiB of dyadic tables for this tier (limit 256 MiB); use v2 or v3");
    }
    dyadic_.resize(tables.segments());
    for (int j = 0; j < tables.segments(); ++j) {
      for (int st = 0; st < 3; ++st) {
        // Every level straight from the balanced Pade (squaring up from the finest level would
        // amplify rounding by 2^34).
        const SegmentSystem& sys = tables.systems[j][st];
        const double d = tables.SegmentLength(j) / tables.substeps[j];
        const double w_ref = ReferenceFrequency(sys.A, tables.n);
        std::vector<Eigen::MatrixXd>& levels = dyadic_[j][st];
        levels.resize(kDyadicLevels);
        for (int l = 0; l < kDyadicLevels; ++l) {
          levels[l] = BalancedExpm(sys.A, d / static_cast<double>(1LL << (l + 1)), tables.n, w_ref);
        }
      }
    }
  }
  if (options.events == EventMethod::kSpectral) {
    spectral_.resize(tables.segments());
    size_t bytes = 0;
    for (int j = 0; j < tables.segments(); ++j) {
      double w_ref = 1.0;
      for (const auto& sys : tables.systems[j])
        w_ref = std::max(w_ref, ReferenceFrequency(sys.A, tables.n));
      for (int st = 0; st < 3; ++st) {
        const SegmentSystem& sys = tables.systems[j][st];
        SpectralSystem& sp = spectral_[j][st];
        sp.decomposition = DecomposeGenerator(sys.A, tables.n, w_ref, tables.SegmentLength(j),
                                              options.spectral_max_condition);
        sp.ok = sp.decomposition.info == SpectralDecomposition::Info::kSuccess;
        if (!sp.ok) {
          ++summary_.spectral_fallback_systems;
          continue;
        }
        summary_.spectral_max_condition =
            std::max(summary_.spectral_max_condition, sp.decomposition.condition);
        sp.drive = ClosedFormGap(sp.decomposition, sys.gap_drive);
        sp.back = ClosedFormGap(sp.decomposition, sys.gap_back);
        bytes += 2 * sizeof(double) * static_cast<size_t>(tables.m) * tables.m;
      }
    }
    summary_.table_bytes += bytes;
    w_.resize(tables.m);
    wt_.resize(tables.m);
    scratch_.resize(tables.m);
  }
  if (options.method == SolverMethod::kFused && tables.segments() >= 2 &&
      options.fusion_levels > 0) {
    int levels = 0;
    while ((2 << levels) <= tables.segments() && levels < options.fusion_levels) ++levels;
    for (int st = 0; st < 3; ++st) {
      runs_[static_cast<size_t>(st)] =
          SegmentRunTable(tables, static_cast<ContactState>(st), levels);
      summary_.table_bytes += runs_[static_cast<size_t>(st)].bytes();
    }
    runs_built_ = true;
    run_scratch_.resize(tables.m);
    input_scratch_.resize(tables.m);
  }
  trajectory_.samples.reserve(reserve_samples);
  trajectory_.events.reserve(reserve_events);
  summary_.table_bytes += tables.TableBytes();
  if (options.record_trajectory) {
    recorder_.emplace(tables, options.samples_per_cycle, &trajectory_);
    piece_z_.resize(tables.m);
    summary_.table_bytes += recorder_->bytes();
  }
}

double ExactStepper::WallTolerance(const Eigen::RowVectorXd& row) const {
  // The gap is a sum of terms that can be much larger than the gap itself (the pair's free rotation
  // drifts), so its rounding floor is ~eps * sum |c_i z_i|; inside that band a state is not moved.
  double magnitude = 0.0;
  for (Eigen::Index i = 0; i < row.size(); ++i) magnitude += std::abs(row[i] * z_[i]);
  return gap_tolerance_ + 64.0 * std::numeric_limits<double>::epsilon() * magnitude;
}

bool ExactStepper::PossibleEvent(const SegmentSystem& sys, bool segment_start) const {
  Wall walls[2];
  const int count = Walls(sys, contact_, walls);
  for (int i = 0; i < count; ++i) {
    const Wall& w = walls[i];
    // The gap rows change at a segment boundary (e_j): the start itself may be outside.
    if (segment_start && w.sign * w.row->dot(z_) > WallTolerance(*w.row)) return true;
    if (w.sign * w.row->dot(z1_) > 0.0) return true;  // crossed by the end of the sub-step
    // Turned towards the wall and back inside the sub-step: an interior extremum to examine.
    const Eigen::RowVectorXd& rate = RateRow(sys, w.row);
    if (w.sign * rate.dot(z_) > 0.0 && w.sign * rate.dot(z1_) < 0.0) return true;
  }
  return false;
}

void ExactStepper::AdvanceExact(int segment, double start, double length, bool record) {
  double done = 0.0;
  double coeff[kTaylorTerms + 1];
  while (length - done > 1e-15 * length) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(contact_)];
    taylor_.col(0) = z_;
    for (int k = 1; k <= kTaylorTerms; ++k) {
      taylor_.col(k).noalias() = sys.A * taylor_.col(k - 1);
      taylor_.col(k) /= static_cast<double>(k);
    }
    summary_.matvecs += kTaylorTerms;
    const double remaining = length - done;
    Wall walls[2];
    const int count = Walls(sys, contact_, walls);
    double best = -1.0;
    int best_wall = -1;
    bool outside_at_start[2] = {false, false};
    for (int i = 0; i < count; ++i) {
      for (int k = 0; k <= kTaylorTerms; ++k)
        coeff[k] = walls[i].sign * walls[i].row->dot(taylor_.col(k));
      // Already outside (the unloaded error jumped at a segment boundary): the contact state is
      // the gap's sign, so the event is now. Within rounding of the wall (just after a located
      // event) we count as inside.
      double root = 0.0;
      outside_at_start[i] = coeff[0] > WallTolerance(*walls[i].row);
      if (!outside_at_start[i]) {
        coeff[0] = std::min(coeff[0], 0.0);
        root = FirstRoot(coeff, kTaylorTerms, remaining, kRootSamples);
      }
      if (root >= 0.0 && (best < 0.0 || root < best)) best = root, best_wall = i;
    }
    const double step = best >= 0.0 ? best : remaining;
    if (tangent_ != nullptr && step > 0.0) PropagateTangentTaylor(sys.A, step);
    // z <- sum_k w_k step^k (Horner over the columns).
    z_ = taylor_.col(kTaylorTerms);
    for (int k = kTaylorTerms - 1; k >= 0; --k) {
      z_ *= step;
      z_ += taylor_.col(k);
    }
    done += step;
    if (best < 0.0) break;
    const Wall& w = walls[best_wall];
    const double rate = RateRow(sys, w.row).dot(z_);
    if (best > 0.0 && std::abs(rate) <= options_.grazing_rate_tolerance) {
      // |g'| ~ 0 at the wall. Curving back inside (h'' < 0): a touch, the state is kept and the
      // search resumes just past it. Otherwise it is a tangential crossing and the state flips.
      for (int k = 0; k <= kTaylorTerms; ++k) coeff[k] = w.sign * w.row->dot(taylor_.col(k));
      double curvature = 0.0, power = 1.0;
      for (int k = 2; k <= kTaylorTerms; ++k, power *= step)
        curvature += k * (k - 1) * coeff[k] * power;
      if (curvature < 0.0) {
        ++summary_.grazing;
        done = std::min(length, done + 1e-12 * length);
        if (++events_this_cycle_ > options_.max_events_per_cycle) return;
        continue;
      }
    }
    SwitchState(sys, best_wall, start + done, record, !outside_at_start[best_wall]);
    if (events_this_cycle_ > options_.max_events_per_cycle) return;
  }
}

int ExactStepper::Outside(const SegmentSystem& sys, const Eigen::VectorXd& z,
                          bool with_tolerance) const {
  Wall walls[2];
  const int count = Walls(sys, contact_, walls);
  for (int i = 0; i < count; ++i) {
    const double tolerance = with_tolerance ? WallTolerance(*walls[i].row) : 0.0;
    if (walls[i].sign * walls[i].row->dot(z) > tolerance) return i;
  }
  return -1;
}

void ExactStepper::SwitchIfOutsideAtStart(int segment, double start, bool record) {
  // At most two switches: free -> contact, and a contact state can never be outside its own wall
  // right after entering it.
  for (int guard = 0; guard < 2; ++guard) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(contact_)];
    const int outside = Outside(sys, z_, true);
    if (outside < 0) return;
    SwitchState(sys, outside, start, record, /*state_triggered=*/false);
  }
}

void ExactStepper::SwitchState(const SegmentSystem& sys, int wall, double time, bool record,
                               bool state_triggered) {
  Wall walls[2];
  Walls(sys, contact_, walls);
  const Wall& w = walls[wall];
  const double rate = RateRow(sys, w.row).dot(z_);
  const ContactState from = contact_;
  contact_ = w.target;
  ++events_this_cycle_;
  if (state_triggered) {
    summary_.min_event_rate = std::min(summary_.min_event_rate, std::abs(rate));
    if (tangent_ != nullptr) {
      // Saltation: V <- V + (f+ - f-) (n^T V) / (n^T f-); n^T f- is the gap rate.
      const SegmentSystem& to = t_.systems[segment_][static_cast<int>(contact_)];
      f_minus_.noalias() = sys.A * z_;
      f_plus_.noalias() = to.A * z_;
      f_plus_ -= f_minus_;
      const double denominator = w.row->dot(f_minus_);
      for (Eigen::Index c = 0; c < tangent_->cols(); ++c) {
        const double along = w.row->dot(tangent_->col(c)) / denominator;
        tangent_->col(c) += along * f_plus_;
      }
    }
  }
  if (!record) return;
  if (piece_open_) {
    // z_ is the state at the event: the piece in the old state ends, one in the new state starts.
    EndPiece(time);
    BeginPiece(time);
  }
  if (from == ContactState::kFree && free_since_ >= 0.0) summary_.separated_s += time - free_since_;
  free_since_ = contact_ == ContactState::kFree ? time : -1.0;
  ++summary_.events;
  if (contact_ == ContactState::kDrive)
    ++summary_.drive_impacts;
  else if (contact_ == ContactState::kBack)
    ++summary_.back_impacts;
  else
    ++summary_.separations;
  if (trajectory_.events.size() < trajectory_.events.capacity()) {
    trajectory_.events.push_back({time, from, contact_, rate});
  }
}

// V1: the sub-step [0, D] is walked on the dyadic grid of depth L = 34. From the current position
// (a multiple of D 2^-L), the largest aligned dyadic step that stays inside the sub-step is tried;
// if its end is outside a wall, the step is halved (bisection) until the crossing is bracketed to
// one grid cell; the event is placed at the cell's end (quantised to D 2^-L) and walking continues
// in the new state. Double crossings within a tried step whose end is inside are found by recursing
// into both halves when the gap turned towards the wall (rates at both ends), like the sub-step
// screen.
void ExactStepper::AdvanceDyadic(int segment, double start, bool record) {
  const long long cells = 1LL << kDyadicLevels;
  const double cell = t_.SegmentLength(segment) / t_.substeps[segment] / static_cast<double>(cells);
  long long pos = 0;
  SwitchIfOutsideAtStart(segment, start, record);
  while (pos < cells) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(contact_)];
    const auto& levels = dyadic_[segment][static_cast<int>(contact_)];
    // Largest aligned step from pos: level l covers 2^(L-1-l) cells... level index for size 2^k
    // cells is L - k - 1... we use sizes 2^k with k = trailing zeros of pos (or L-1 at pos = 0).
    int k = pos == 0 ? kDyadicLevels - 1 : __builtin_ctzll(static_cast<unsigned long long>(pos));
    while (pos + (1LL << k) > cells) --k;
    bool crossed = false;
    while (true) {
      const Eigen::MatrixXd& step = levels[kDyadicLevels - 1 - k];
      zb_.noalias() = step * z_;
      ++summary_.matvecs;
      Wall walls[2];
      const int count = Walls(sys, contact_, walls);
      bool suspect = false;
      for (int i = 0; i < count; ++i) {
        const Wall& w = walls[i];
        if (w.sign * w.row->dot(zb_) > 0.0) suspect = true;
        const Eigen::RowVectorXd& rate = RateRow(sys, w.row);
        if (k > 0 && w.sign * rate.dot(z_) > 0.0 && w.sign * rate.dot(zb_) < 0.0 &&
            w.sign * w.row->dot(zb_) > -1e-3 * t_.half_backlash) {
          suspect = true;  // turned back near the wall: look inside
        }
      }
      if (!suspect) break;
      if (k == 0) {
        crossed = true;
        break;
      }
      --k;  // bisect: try the first half
    }
    z_.swap(zb_);
    if (tangent_ != nullptr) PropagateTangent(levels[kDyadicLevels - 1 - k]);
    pos += 1LL << k;
    if (crossed) {
      const SegmentSystem& now = t_.systems[segment][static_cast<int>(contact_)];
      const int outside = Outside(now, z_, false);
      if (outside >= 0) {
        SwitchState(now, outside, start + static_cast<double>(pos) * cell, record,
                    /*state_triggered=*/true);
      }
      if (events_this_cycle_ > options_.max_events_per_cycle) return;
    }
  }
}

void ExactStepper::BeginPiece(double time) {
  piece_z_ = z_;
  piece_start_ = time;
  piece_state_ = contact_;
  piece_open_ = true;
}

void ExactStepper::EndPiece(double time) {
  piece_open_ = false;
  recorder_->Piece(segment_, piece_state_, piece_start_, time - piece_start_, piece_z_);
}

bool ExactStepper::Run(long cycles, bool record) {
  const double run_start = static_cast<double>(cycle_) * t_.mesh_period;
  if (record && contact_ == ContactState::kFree && free_since_ < 0.0) free_since_ = run_start;
  const bool recorded = record && recorder_.has_value();
  if (recorded && !recording_) {
    recorder_->Start(run_start);
    recording_ = true;
  }
  for (long c = 0; c < cycles; ++c, ++cycle_) {
    if (options_.Cancelled()) throw RunCancelled();
    events_this_cycle_ = 0;
    const double cycle_start = static_cast<double>(cycle_) * t_.mesh_period;
    for (int j = 0; j < t_.segments(); ++j) {
      segment_ = j;
      const double h = t_.SegmentLength(j);
      const double seg_start = cycle_start + t_.boundaries[j];
      if (runs_built_ && !fused_ && tangent_ == nullptr && !options_.ignore_walls && !recorded) {
        // A certified run of segments in one matvec (segment_runs.h), end state checked.
        const SegmentRun* run = runs_[static_cast<size_t>(contact_)].Certify(j, z_, run_scratch_);
        if (run != nullptr) {
          z1_ = z_;
          z1_.tail(t_.inputs).setZero();
          zb_.noalias() = run->product * z1_;
          for (int i = 0; i < run->length; ++i) {
            t_.SetInputs(cycle_, j + i, input_scratch_);
            for (int q = 0; q < t_.inputs; ++q) {
              const double u = input_scratch_[t_.input_slot(q)];
              if (u != 0.0) zb_ += u * run->inputs.col(i * t_.inputs + q);
            }
          }
          const SegmentSystem& last = t_.systems[j + run->length - 1][static_cast<int>(contact_)];
          if (Outside(last, zb_, false) < 0) {
            z_.swap(zb_);
            ++summary_.matvecs;
            summary_.run_fused_segments += run->length;
            j += run->length - 1;
            time_ = cycle_start + t_.boundaries[j + 1];
            continue;
          }
        }
      }
      t_.SetInputs(cycle_, j, z_);
      if (recorded) BeginPiece(seg_start);
      if (fused_ || options_.ignore_walls) {
        // Certified contact: the whole segment in one matvec (no wall can be reached).
        const Eigen::MatrixXd& full = t_.systems[j][static_cast<int>(contact_)].full;
        z1_.noalias() = full * z_;
        z_.swap(z1_);
        if (tangent_ != nullptr) PropagateTangent(full);
        ++summary_.matvecs;
        time_ = seg_start + h;
        if (recorded) EndPiece(time_);
        continue;
      }
      if (options_.events == EventMethod::kSpectral) {
        AdvanceSpectral(j, seg_start, record);
        if (events_this_cycle_ > options_.max_events_per_cycle) return TooManyEvents();
        time_ = seg_start + h;
        if (recorded) EndPiece(time_);
        continue;
      }
      const int n = t_.substeps[j];
      const double d = h / n;
      for (int i = 0; i < n; ++i) {
        const SegmentSystem& sys = t_.systems[j][static_cast<int>(contact_)];
        z1_.noalias() = sys.substep * z_;
        ++summary_.matvecs;
        if (!PossibleEvent(sys, i == 0)) {
          z_.swap(z1_);
          if (tangent_ != nullptr) PropagateTangent(sys.substep);
        } else {
          if (options_.events == EventMethod::kDyadic) {
            AdvanceDyadic(j, seg_start + i * d, record);
          } else {
            AdvanceExact(j, seg_start + i * d, d, record);
          }
          if (events_this_cycle_ > options_.max_events_per_cycle) return TooManyEvents();
        }
      }
      time_ = seg_start + h;
      if (recorded) EndPiece(time_);
    }
    ++summary_.mesh_cycles;
    if (fused_) ++summary_.fused_cycles;
    if (record) {
      summary_.recorded_s += t_.mesh_period;
      ++summary_.recorded_cycles;
    }
    // Remove the drift of the pair's free rotation (exactly invariant; see SegmentTables).
    const double drift = t_.recenter_row.dot(z_.head(t_.n));
    z_.head(t_.n) -= drift * t_.rigid_rotation;
    if (tangent_ != nullptr) {
      RemoveFreeRotation(t_, *tangent_);
      tangent_->bottomRows(1 + t_.inputs).setZero();
    }
  }
  return true;
}

void ExactStepper::AttachTangent(Eigen::MatrixXd* tangent) {
  tangent_ = tangent;
  if (tangent == nullptr) return;
  if (tangent->rows() != t_.m) {
    throw std::invalid_argument("ExactStepper::AttachTangent: the tangent needs m rows");
  }
  tangent_next_.resize(t_.m, tangent->cols());
  tangent_w_.resize(t_.m, tangent->cols());
  f_minus_.resize(t_.m);
  f_plus_.resize(t_.m);
  tangent_col_.resize(t_.m);
  if (wt_.size() != t_.m) {
    w_.resize(t_.m);
    wt_.resize(t_.m);
    scratch_.resize(t_.m);
  }
}

void ExactStepper::Restart(const Eigen::VectorXd& z, ContactState state) {
  z_ = z;
  contact_ = state;
  cycle_ = 0;
  time_ = 0.0;
  events_this_cycle_ = 0;
  free_since_ = -1.0;
  fused_ = false;
  SolverSummary fresh;
  fresh.table_bytes = summary_.table_bytes;
  fresh.spectral_fallback_systems = summary_.spectral_fallback_systems;
  fresh.spectral_max_condition = summary_.spectral_max_condition;
  summary_ = fresh;
  trajectory_.samples.clear();
  trajectory_.events.clear();
  trajectory_.statistics = TrajectoryStatistics{};
  recording_ = false;
  piece_open_ = false;
}

void ExactStepper::PropagateTangent(const Eigen::MatrixXd& propagator) {
  tangent_next_.noalias() = propagator * *tangent_;
  tangent_->swap(tangent_next_);
}

void ExactStepper::PropagateTangentTaylor(const Eigen::MatrixXd& A, double step) {
  // expm(A step) V = V + A step (V + A step / 2 (V + ...)) (Horner); rho(A) step <= 1/2 here, so
  // kTaylorTerms terms reach rounding as for the state.
  tangent_w_ = *tangent_;
  for (int k = kTaylorTerms; k >= 1; --k) {
    tangent_next_.noalias() = A * tangent_w_;
    tangent_w_ = *tangent_ + (step / static_cast<double>(k)) * tangent_next_;
  }
  tangent_->swap(tangent_w_);
}

void ExactStepper::PropagateTangentDecoupled(const SpectralDecomposition& d, double step) {
  tangent_w_.noalias() = d.S_inv * *tangent_;
  for (Eigen::Index c = 0; c < tangent_->cols(); ++c) {
    tangent_col_ = tangent_w_.col(c);
    PropagateDecoupled(d, tangent_col_, step, wt_, scratch_);
    tangent_w_.col(c) = wt_;
  }
  tangent_->noalias() = d.S * tangent_w_;
  // The decomposition leaks rounding into the constant and input slots; a tangent entry there
  // would act as a neutral (multiplier-1) forcing perturbation and pin the exponent at 0.
  tangent_->bottomRows(1 + t_.inputs).setZero();
}

bool ExactStepper::TooManyEvents() {
  summary_.status = SolverStatus::kTooManyEvents;
  summary_.message = "more than " + std::to_string(options_.max_events_per_cycle) +
                     " contact events in mesh cycle " + std::to_string(cycle_);
  return false;
}

void ExactStepper::AdvanceTaylorFrom(int segment, double start, double done, bool record) {
  const double h = t_.SegmentLength(segment);
  const double d = h / t_.substeps[segment];
  while (h - done > 1e-15 * h) {
    const double length = std::min(d, h - done);
    AdvanceExact(segment, start + done, length, record);
    done += length;
    if (events_this_cycle_ > options_.max_events_per_cycle) return;
  }
}

// V3 over one whole segment: see the header and spectral_gap.h.
void ExactStepper::AdvanceSpectral(int segment, double start, bool record) {
  const double h = t_.SegmentLength(segment);
  SwitchIfOutsideAtStart(segment, start, record);
  double done = 0.0;
  bool moved = false;  // z_ was advanced inside this segment (the full propagator no longer fits)
  while (true) {
    const SegmentSystem& sys = t_.systems[segment][static_cast<int>(contact_)];
    SpectralSystem& sp = spectral_[segment][static_cast<int>(contact_)];
    if (!sp.ok) {
      AdvanceTaylorFrom(segment, start, done, record);
      return;
    }
    const double remaining = h - done;
    w_.noalias() = sp.decomposition.S_inv * z_;
    ++summary_.matvecs;
    Wall walls[2];
    const int count = Walls(sys, contact_, walls);
    double best = -1.0;
    int best_wall = -1;
    for (int i = 0; i < count; ++i) {
      ClosedFormGap& gap = walls[i].row == &sys.gap_drive ? sp.drive : sp.back;
      gap.Load(w_);
      const double root = gap.FirstRise(walls[i].sign, remaining);
      if (root >= 0.0 && (best < 0.0 || root < best)) best = root, best_wall = i;
    }
    if (best < 0.0) {
      if (!moved) {
        z1_.noalias() = sys.full * z_;  // the dense propagator: exact to rounding, cond-free
        if (tangent_ != nullptr) PropagateTangent(sys.full);
      } else {
        PropagateDecoupled(sp.decomposition, w_, remaining, wt_, scratch_);
        z1_.noalias() = sp.decomposition.S * wt_;
        if (tangent_ != nullptr) PropagateTangentDecoupled(sp.decomposition, remaining);
      }
      z_.swap(z1_);
      ++summary_.matvecs;
      return;
    }
    const Wall& w = walls[best_wall];
    ClosedFormGap& gap = w.row == &sys.gap_drive ? sp.drive : sp.back;
    double step = best;
    const double rate = gap.Rate(best);
    const bool touch = best > 0.0 && std::abs(rate) <= options_.grazing_rate_tolerance &&
                       w.sign * gap.Curvature(best) < 0.0;
    // A grazing touch keeps the state; the search resumes just past it.
    if (touch) step = std::min(remaining, best + 1e-12 * h);
    PropagateDecoupled(sp.decomposition, w_, step, wt_, scratch_);
    z_.noalias() = sp.decomposition.S * wt_;
    if (tangent_ != nullptr) PropagateTangentDecoupled(sp.decomposition, step);
    ++summary_.matvecs;
    moved = true;
    done += step;
    if (touch) {
      ++summary_.grazing;
      if (++events_this_cycle_ > options_.max_events_per_cycle) return;
    } else {
      SwitchState(sys, best_wall, start + done, record, /*state_triggered=*/true);
      if (events_this_cycle_ > options_.max_events_per_cycle) return;
    }
    if (h - done <= 1e-15 * h) return;
  }
}

void ExactStepper::JumpTo(const Eigen::VectorXd& z, long cycles) {
  z_ = z;
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
  const size_t samples =
      static_cast<size_t>(std::min(wanted_samples, options.max_trajectory_samples));
  const size_t events =
      static_cast<size_t>(std::min(options.cycles * 16, options.max_logged_events));
  ExactStepper stepper(tables, options, z0, state0, samples, events);
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
    if (!cycle || cycle->state() != state) cycle.emplace(tables, state);
    if (!cycle->Certify(stepper.state()).certified) return;
    stepper.summary().contact_certified = true;
    stepper.SetFusedContact(true);
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
  const double recorded = static_cast<double>(options.cycles);
  s.events_per_cycle = static_cast<double>(s.events) / recorded;
  s.matvec_per_cycle =
      static_cast<double>(s.matvecs) / static_cast<double>(std::max<long>(s.mesh_cycles, 1));
  result.trajectory = std::move(stepper.trajectory());
  result.final_state = stepper.state();
  result.final_contact = stepper.contact();
  return result;
}

}  // namespace gearnvh
