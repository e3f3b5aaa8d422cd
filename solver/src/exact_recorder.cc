#include "gearnvh/solver/exact_recorder.h"

#include <algorithm>
#include <cmath>

#include "bracketed_newton.h"

namespace gearnvh {

namespace {

constexpr int K = ExactRecorder::kTerms;

// Coefficients a_0..a_d of p(s) = sum a_k s^k on [0, L].
struct Poly {
  const double* a;
  int d;
  double Value(double s) const {
    double v = a[d];
    for (int k = d - 1; k >= 0; --k) v = v * s + a[k];
    return v;
  }
  double Slope(double s) const {
    if (d == 0) return 0.0;
    double v = d * a[d];
    for (int k = d - 1; k >= 1; --k) v = v * s + k * a[k];
    return v;
  }
  double Curvature(double s) const {
    if (d < 2) return 0.0;
    double v = d * (d - 1) * a[d];
    for (int k = d - 1; k >= 2; --k) v = v * s + k * (k - 1) * a[k];
    return v;
  }
  // int_0^L (p(s) - offset) ds.
  double Integral(double L, double offset) const {
    auto coefficient = [&](int k) { return k == 0 ? a[0] - offset : a[k]; };
    double v = coefficient(d) / (d + 1);
    for (int k = d - 1; k >= 0; --k) v = v * L + coefficient(k) / (k + 1);
    return v * L;
  }
  // int_0^L (p(s) - offset)^2 ds: the square's coefficients, then their integral.
  double SquareIntegral(double L, double offset) const {
    double b[2 * K + 1] = {};
    for (int k = 0; k <= d; ++k) {
      const double ak = k == 0 ? a[0] - offset : a[k];
      for (int l = 0; l <= d; ++l) b[k + l] += ak * (l == 0 ? a[0] - offset : a[l]);
    }
    double v = b[2 * d] / (2 * d + 1);
    for (int j = 2 * d - 1; j >= 0; --j) v = v * L + b[j] / (j + 1);
    return v * L;
  }
  // sup |p''| on [0, L].
  double CurvatureBound(double L) const {
    double bound = 0.0, power = 1.0;
    for (int k = 2; k <= d; ++k, power *= L) bound += k * (k - 1) * std::abs(a[k]) * power;
    return bound;
  }
};

// The polynomial of a[0..K] without the trailing terms that cannot change its value on [0, L].
Poly Trimmed(const double* a, double L) {
  double size = 0.0, power = 1.0;
  double terms[K + 1];
  for (int k = 0; k <= K; ++k, power *= L) {
    terms[k] = std::abs(a[k]) * power;
    size += terms[k];
  }
  int d = K;
  while (d > 0 && terms[d] <= 1e-18 * size) --d;
  return {a, d};
}

void Consider(OutputStatistics& st, double value, double time, bool want_min) {
  if (value > st.max) st.max = value, st.time_of_max = time;
  if (want_min && value < st.min) st.min = value, st.time_of_min = time;
}

// Every extremum of p on [0, L] that can beat the running ones (see the header).
void UpdateExtrema(const Poly& p, double L, double t0, OutputStatistics& st, bool want_min) {
  Consider(st, p.Value(0.0), t0, want_min);
  Consider(st, p.Value(L), t0 + L, want_min);
  if (p.d < 2) return;
  const double b2 = p.CurvatureBound(L);
  constexpr int kMaxDepth = 48;
  auto search = [&](auto&& self, double lo, double hi, double p_lo, double p_hi, double d_lo,
                    double d_hi, int depth) -> void {
    const double width = hi - lo;
    const double slack = 0.125 * b2 * width * width;
    const bool can_max = std::max(p_lo, p_hi) + slack > st.max;
    const bool can_min = want_min && std::min(p_lo, p_hi) - slack < st.min;
    if (!can_max && !can_min) return;
    const bool sign_change = (d_lo > 0.0) != (d_hi > 0.0);
    if (!sign_change && std::abs(d_lo) + std::abs(d_hi) > b2 * width) return;  // monotone
    if (depth >= kMaxDepth) {
      Consider(st, p.Value(0.5 * (lo + hi)), t0 + 0.5 * (lo + hi), want_min);
      return;
    }
    double split = 0.5 * (lo + hi);
    if (sign_change) {
      // p' changes sign: locate the root (a stationary point) and split there.
      const double sign = d_lo <= 0.0 ? 1.0 : -1.0;
      split = BracketedNewton([&](double s) { return sign * p.Slope(s); },
                              [&](double s) { return sign * p.Curvature(s); }, lo, hi,
                              0.5 * (lo + hi), 1e-16 * L);
      split = std::clamp(split, lo, hi);
      if (split <= lo || split >= hi) split = 0.5 * (lo + hi);
    }
    const double p_split = p.Value(split);
    Consider(st, p_split, t0 + split, want_min);
    const double d_split = p.Slope(split);
    self(self, lo, split, p_lo, p_split, d_lo, d_split, depth + 1);
    self(self, split, hi, p_split, p_hi, d_split, d_hi, depth + 1);
  };
  constexpr int kStart = 4;
  double lo = 0.0, p_lo = p.Value(0.0), d_lo = p.Slope(0.0);
  for (int i = 1; i <= kStart; ++i) {
    const double hi = L * i / kStart;
    const double p_hi = p.Value(hi), d_hi = p.Slope(hi);
    search(search, lo, hi, p_lo, p_hi, d_lo, d_hi, 0);
    lo = hi, p_lo = p_hi, d_lo = d_hi;
  }
}

void Accumulate(OutputStatistics& st, const Poly& p, double L) {
  if (!st.has_offset) st.offset = p.a[0], st.has_offset = true;
  st.integral += static_cast<long double>(p.Integral(L, st.offset));
  st.square_integral += static_cast<long double>(p.SquareIntegral(L, st.offset));
}

}  // namespace

double OutputStatistics::Mean(double duration) const {
  if (!(duration > 0.0)) return 0.0;
  return offset + static_cast<double>(integral / duration);
}

double OutputStatistics::Rms(double duration) const {
  if (!(duration > 0.0)) return 0.0;
  const long double mean = integral / duration;
  const long double variance = square_integral / duration - mean * mean;
  return std::sqrt(static_cast<double>(std::max(variance, 0.0L)));
}

ExactRecorder::ExactRecorder(const SegmentTables& tables, int samples_per_cycle, Trajectory* out)
    : t_(tables),
      sample_step_(tables.mesh_period / std::max(samples_per_cycle, 1)),
      coefficients_(kOutputs * (K + 1)),
      chunk_z_(tables.m),
      next_z_(tables.m),
      out_(out) {
  rows_.resize(static_cast<size_t>(tables.segments()));
  for (int j = 0; j < tables.segments(); ++j) {
    for (int st = 0; st < 3; ++st) {
      const SegmentSystem& sys = tables.systems[static_cast<size_t>(j)][st];
      Eigen::MatrixXd r(kOutputs, tables.m);
      r.row(0) = tables.te_row;
      if (st == static_cast<int>(ContactState::kDrive)) {
        r.row(1) = sys.mesh_stiffness * sys.gap_drive + tables.mesh_damping * sys.gap_drive_rate;
      } else if (st == static_cast<int>(ContactState::kBack)) {
        r.row(1) = -(sys.mesh_stiffness * sys.gap_back + tables.mesh_damping * sys.gap_back_rate);
      } else {
        r.row(1).setZero();
      }
      r.row(2) = tables.pinion_rate_row;
      r.row(3) = tables.wheel_rate_row;
      Eigen::MatrixXd& rows = rows_[static_cast<size_t>(j)][st];
      rows.resize(kOutputs * (K + 1), tables.m);
      for (int o = 0; o < kOutputs; ++o) {
        Eigen::RowVectorXd term = r.row(o);
        for (int k = 0; k <= K; ++k) {
          rows.row(o * (K + 1) + k) = term;
          term = (term * sys.A / static_cast<double>(k + 1)).eval();
        }
      }
    }
  }
}

void ExactRecorder::Start(double time) {
  window_start_ = time;
  next_sample_ = 0;
}

size_t ExactRecorder::bytes() const {
  size_t total = 0;
  for (const auto& per_state : rows_) {
    for (const Eigen::MatrixXd& r : per_state) total += sizeof(double) * r.size();
  }
  return total;
}

void ExactRecorder::Piece(int segment, ContactState state, double start, double length,
                          const Eigen::VectorXd& z) {
  if (!(length > 0.0)) return;
  const SegmentSystem& sys = t_.systems[static_cast<size_t>(segment)][static_cast<int>(state)];
  const Eigen::MatrixXd& rows = rows_[static_cast<size_t>(segment)][static_cast<int>(state)];
  const double step = t_.SegmentLength(segment) / t_.substeps[static_cast<size_t>(segment)];
  const int chunks = std::max(1, static_cast<int>(std::ceil(length / step - 1e-9)));
  chunk_z_ = z;
  for (int c = 0; c < chunks; ++c) {
    const double offset = c * step;
    const double len = c + 1 == chunks ? length - offset : step;
    Chunk(rows, start + offset, len, chunk_z_, state);
    if (c + 1 < chunks) {
      next_z_.noalias() = sys.substep * chunk_z_;
      chunk_z_.swap(next_z_);
    }
  }
  ++out_->statistics.pieces;
  out_->statistics.duration += length;
}

void ExactRecorder::Chunk(const Eigen::MatrixXd& rows, double start, double length,
                          const Eigen::VectorXd& z, ContactState state) {
  TrajectoryStatistics& stats = out_->statistics;
  std::vector<TrajectorySample>& samples = out_->samples;
  ++stats.chunks;
  coefficients_.noalias() = rows * z;
  const double* a = coefficients_.data();
  const Poly te = Trimmed(a, length);
  const Poly force = Trimmed(a + (K + 1), length);
  const Poly pinion = Trimmed(a + 2 * (K + 1), length);
  const Poly wheel = Trimmed(a + 3 * (K + 1), length);
  // The wheel's acceleration is its velocity's derivative: coefficients (k + 1) a_{k+1}.
  double accel_coefficients[K + 1] = {};
  for (int k = 0; k < wheel.d; ++k) accel_coefficients[k] = (k + 1) * wheel.a[k + 1];
  const Poly accel{accel_coefficients, std::max(wheel.d - 1, 0)};

  Accumulate(stats.te, te, length);
  UpdateExtrema(te, length, start, stats.te, true);
  Accumulate(stats.wheel_acceleration, accel, length);
  Accumulate(stats.mesh_force, force, length);
  if (state != ContactState::kFree) {
    UpdateExtrema(force, length, start, stats.mesh_force, false);
  } else {
    Consider(stats.mesh_force, 0.0, start, false);
  }

  // A sample on the chunk's end belongs to the next piece (and the window's end to none).
  const double end = start + length - 1e-9 * sample_step_;
  for (double time = window_start_ + static_cast<double>(next_sample_) * sample_step_; time < end;
       time = window_start_ + static_cast<double>(++next_sample_) * sample_step_) {
    if (samples.size() >= samples.capacity()) {
      ++dropped_;
      continue;
    }
    const double s = time - start;
    TrajectorySample sample;
    sample.time = time;
    sample.te = te.Value(s);
    sample.te_rate = te.Slope(s);
    sample.mesh_force = force.Value(s);
    sample.pinion_speed = pinion.Value(s);
    sample.wheel_speed = wheel.Value(s);
    sample.wheel_acceleration = accel.Value(s);
    sample.state = state;
    samples.push_back(sample);
  }
}

}  // namespace gearnvh
