#include "gearnvh/solver/exact_recorder.h"

#include <algorithm>
#include <cmath>

#include "gearnvh/solver/cycle_output_rows.h"
#include "gearnvh/solver/solver_options.h"
#include "polynomial_statistics.h"

namespace gearnvh {

using polynomial_statistics::Accumulate;
using polynomial_statistics::Consider;
using polynomial_statistics::Poly;
using polynomial_statistics::UpdateExtrema;

namespace {

constexpr int K = ExactRecorder::kTerms;

Poly Trimmed(const double* a, double L) { return polynomial_statistics::Trimmed(a, K, L); }

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

ExactRecorder::ExactRecorder(const SegmentTables& tables, int samples_per_cycle, Trajectory* out,
                             const std::atomic<bool>* cancel)
    : t_(tables),
      sample_step_(tables.mesh_period / std::max(samples_per_cycle, 1)),
      coefficients_(kOutputs * (K + 1)),
      chunk_z_(tables.m),
      next_z_(tables.m),
      out_(out) {
  rows_.resize(static_cast<size_t>(tables.segments()));
  for (int j = 0; j < tables.segments(); ++j) {
    ThrowIfCancelled(cancel);
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

void ExactRecorder::RowCycle(CycleOutputRows& rows, long cycle, double cycle_start,
                             const Eigen::VectorXd& z) {
  rows.Record(cycle, cycle_start, z, window_start_, next_sample_, dropped_, *out_);
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
