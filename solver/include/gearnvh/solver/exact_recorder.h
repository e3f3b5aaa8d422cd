// Exact statistics and uniformly sampled outputs of a recorded trajectory (docs/design.md §10).
//
// The stepper hands over the recorded trajectory as pieces: the state z at the start of a piece,
// the (segment, contact state) whose generator A propagates it, the start time and the length.
// Inside a piece every output is a row on the state, y(t) = r e^{A t} z, and is evaluated exactly:
// the piece is cut into chunks no longer than the segment's sub-step D (rho(A) D <= 1/2, rho the
// spectral radius), and on a chunk starting at z_c
//   y(s) = sum_{k=0..K} (r A^k / k!) z_c s^k,   K = 18,
// whose truncation error (rho s)^19 / 19! ~ 1e-23 is below rounding (the rows r A^k / k! are
// precomputed per segment and state, so a chunk costs one small matrix-vector product; the state
// moves to the next chunk by the sub-step propagator). On each chunk:
//   integrals     int y ds and int y^2 ds in closed form from the polynomial's coefficients;
//   extrema       the endpoints and every root of y' (bracketed from samples of y', certified by
//                 |y''| <= B2 = sum k(k-1)|a_k| L^(k-2): an interval with |y'(a)| + |y'(b)| >
//                 B2 (b - a) holds no root; intervals that cannot beat the running extreme, by
//                 max(y(a), y(b)) + B2 (b - a)^2 / 8, are skipped);
//   samples       y at the uniform sample times t_0 + k T_m / P inside the chunk.
// Outputs: the dynamic TE delta = v^T x (its rate is the derivative of its polynomial), the mesh
// force (drive: k g+ + c g+'; back: -(k g- + c g-'); free: 0), the running angular velocities of
// pinion and wheel, and the wheel's angular acceleration (the derivative of its velocity).
// Nothing is taken from segment-boundary samples, and a peak between two boundaries is found.
// Construction allocates every table and the sample buffer; Piece() does not allocate.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <vector>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/trajectory.h"

namespace gearnvh {

class CycleOutputRows;

class ExactRecorder {
 public:
  // Writes samples and statistics into *out; `samples_per_cycle` uniform samples per mesh cycle
  // (>= 1), at most out->samples.capacity() stored (reserve before recording).
  // `cancel` (SolverOptions::cancel) is polled per segment of the rows' build.
  ExactRecorder(const SegmentTables& tables, int samples_per_cycle, Trajectory* out,
                const std::atomic<bool>* cancel = nullptr);

  // The recorded window starts at `time` (samples at time + k T_m / P).
  void Start(double time);
  // The trajectory from z (at `start`, in `state`, inside `segment`) for `length` seconds.
  void Piece(int segment, ContactState state, double start, double length,
             const Eigen::VectorXd& z);
  // Samples that did not fit the reserved capacity (counted, not stored).
  long dropped_samples() const { return dropped_; }
  size_t bytes() const;

  // Mesh cycle `cycle` (starting at `cycle_start`) from z at its start by the output rows of a
  // certified cycle (cycle_output_rows.h): the same samples and statistics as its pieces.
  void RowCycle(CycleOutputRows& rows, long cycle, double cycle_start, const Eigen::VectorXd& z);
  // The rows r_o A^k / k! of (segment, state): kOutputs (K + 1) x m, block o row k.
  const Eigen::MatrixXd& chunk_rows(int segment, ContactState state) const {
    return rows_[static_cast<size_t>(segment)][static_cast<int>(state)];
  }

  static constexpr int kTerms = 18;   // K
  static constexpr int kOutputs = 4;  // TE, mesh force, pinion speed, wheel speed

 private:
  void Chunk(const Eigen::MatrixXd& rows, double start, double length, const Eigen::VectorXd& z,
             ContactState state);

  const SegmentTables& t_;
  double sample_step_ = 0.0, window_start_ = 0.0;
  long next_sample_ = 0;
  long dropped_ = 0;
  // rows_[segment][state]: kOutputs (K + 1) x m, block o row k = r_o A^k / k!.
  std::vector<std::array<Eigen::MatrixXd, 3>> rows_;
  Eigen::VectorXd coefficients_, chunk_z_, next_z_;
  Trajectory* out_;
};

}  // namespace gearnvh
