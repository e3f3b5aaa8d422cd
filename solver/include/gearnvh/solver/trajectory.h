// The recorded part of a run: uniform samples, the contact events, and exact statistics
// (solver/exact_recorder.h computes them from the piecewise-exact solution).
#pragma once

#include <limits>
#include <vector>

#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

// Running integrals and extrema of one scalar output over the recorded time.
struct OutputStatistics {
  // Integrals of y - offset (offset = the first value seen) in extended precision, so the mean and
  // RMS keep their digits when the mean is much larger than the fluctuation.
  long double integral = 0.0L, square_integral = 0.0L;
  double offset = 0.0;
  bool has_offset = false;
  double max = -std::numeric_limits<double>::infinity();
  double min = std::numeric_limits<double>::infinity();
  double time_of_max = 0.0, time_of_min = 0.0;

  // Over a recorded duration T (s): (1/T) int y dt and sqrt((1/T) int (y - mean)^2 dt).
  double Mean(double duration) const;
  double Rms(double duration) const;
};

struct TrajectoryStatistics {
  double duration = 0.0;                // recorded time, s
  OutputStatistics te;                  // m
  OutputStatistics mesh_force;          // N
  OutputStatistics wheel_acceleration;  // rad/s^2 (integrals only)
  long pieces = 0, chunks = 0;
  long row_cycles = 0;  // cycles recorded by output rows (cycle_output_rows.h); in pieces/chunks
};

struct TrajectorySample {
  double time = 0.0;          // s
  double te = 0.0;            // dynamic transmission error v^T x, m
  double te_rate = 0.0;       // its time derivative, m/s
  double mesh_force = 0.0;    // N (positive on the drive flank)
  double pinion_speed = 0.0;  // running angular velocity perturbation, rad/s
  double wheel_speed = 0.0;
  double wheel_acceleration = 0.0;  // running angular acceleration of the wheel, rad/s^2
  ContactState state{};
};

struct EventRecord {
  double time = 0.0;  // s since the start of the run
  ContactState from = ContactState::kFree, to = ContactState::kFree;
  double gap_rate = 0.0;  // m/s, d/dt of the gap crossing its wall
};

struct Trajectory {
  // Uniform samples (SolverOptions::samples_per_cycle per mesh cycle) from the start of the
  // recorded window, evaluated exactly at their times.
  std::vector<TrajectorySample> samples;
  std::vector<EventRecord> events;  // of the recorded cycles
  TrajectoryStatistics statistics;
};

}  // namespace gearnvh
