// Recorded cycles of certified permanent contact as output rows (docs/solver.md, Recording;
// docs/design.md §4.3): one cycle-map matvec per mesh cycle plus a few rows on the state, instead
// of one matvec per segment and one coefficient block per chunk.
//
// In certified contact without inputs every output of a cycle is linear in the state z at its
// start (ExactRecorder: on chunk c the output is p_c(s) = sum_k (r A^k / k!) Phi_c z s^k, Phi_c the
// propagator from the cycle start). The state is written on a basis
//   z = y* + [r;0] p + [0;r] v + sum_i V_i q_i,   x = [1; p; v; q],
// y* the cycle map's periodic orbit (ConstantContactCycle), p and v the pair's free rotation and
// its velocity (p = r~ . x_pos, v = r~ . x_vel), V_i the real and imaginary parts of the quotient
// map's eigenvectors (a complex pair lambda, conj(lambda) gives two columns), q their real modal
// coordinates (rows of V^-1 L). Propagating the columns through one cycle gives, per chunk and
// output, a coefficient matrix C_c (19 x (K + 1)) with p_c(s) = (C_c x)(s); from them, once:
//   samples           y(t_s) = S x             (6 rows per sample: TE, its rate, force, speeds,
//                                                wheel acceleration),
//   integrals         int (y - y0) dt = J x,   int (y - y0)^2 dt = x^T G x   (y0 = the orbit's
//                     value at the cycle start; G = sum_c C_c^T H_c C_c, H_c[k][l] =
//                     L_c^(k+l+1) / (k+l+1)),
//   extrema           the orbit's extremum per chunk and the bound |p_c(s) - orbit| <= sum_j |x_j|
//                     g_j (g_j = max_c sum_k |C_c[k][j]| L_c^k): only chunks whose bound reaches
//                     the running extremum are evaluated, by the recorder's own certified search
//                     on C_c x, so the extrema and their times are the chunk-by-chunk ones.
// Dead modes: a mode contributes at most |q_i(k0)| |lambda_i|^(k - k0) g_i to any output in cycle
// k; once that is below 2^-56 of the output's scale (its largest value on the orbit), the mode's
// column is dropped (columns are ordered by |lambda| descending, so the live ones are a prefix of
// K columns and a cycle costs K (m + rows) instead of m^2 per segment). The state itself is
// advanced by the exact cycle map, so nothing is dropped from it.
// Applies when ConstantContactCycle has certified contact forever (no events can occur) and the
// tables have no engine excitation or manufacturing error; refused (usable() false) when the
// eigenbasis cannot reproduce a deviation to 1e-10.
#pragma once

#include <Eigen/Dense>
#include <array>
#include <atomic>
#include <vector>

#include "gearnvh/solver/cycle_map.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/trajectory.h"

namespace gearnvh {

class ExactRecorder;

class CycleOutputRows {
 public:
  // `cancel` (SolverOptions::cancel) is polled per segment of the columns' propagation.
  CycleOutputRows(const SegmentTables& tables, const ConstantContactCycle& cycle,
                  const ExactRecorder& recorder, int samples_per_cycle,
                  const std::atomic<bool>* cancel = nullptr);
  bool usable() const { return usable_; }
  // Starts a stretch of row cycles in mesh cycle `cycle` from z (at its start): the modal
  // amplitudes fix the cycle after which each mode is dead.
  void Enter(long cycle, const Eigen::VectorXd& z);
  bool entered() const { return entered_; }
  void Leave() { entered_ = false; }
  // Records mesh cycle `cycle` (starting at `cycle_start` s) from z at its start: samples from
  // index next_sample (window start + index * T / P), statistics, extrema.
  void Record(long cycle, double cycle_start, const Eigen::VectorXd& z, double window_start,
              long& next_sample, long& dropped, Trajectory& out);
  const Eigen::MatrixXd& map() const { return cycle_.map(); }
  int live_columns() const { return live_; }  // K of the last recorded cycle
  size_t bytes() const;

  static constexpr int kSampleValues = 6;  // TE, TE rate, force, pinion, wheel, wheel accel.

 private:
  struct Chunk {
    int segment = 0;
    double in_segment = 0.0, length = 0.0;  // start within its segment and length, s
  };
  // Per output with statistics (TE, mesh force, wheel acceleration).
  struct Statistic {
    Eigen::RowVectorXd integral;   // J
    Eigen::MatrixXd square;        // G
    double reference = 0.0;        // y0
    Eigen::RowVectorXd start_row;  // the output at the cycle start (the recorder's offset)
    Eigen::VectorXd gain;          // g_j (per column; column 0 unused)
    // Per chunk: the coefficient matrix C_c (extrema only) and the orbit's extrema on it.
    std::vector<Eigen::MatrixXd> coefficients;
    std::vector<double> orbit_max, orbit_min;
    std::vector<int> by_max, by_min;  // chunks by orbit_max descending / orbit_min ascending
    double scale = 0.0;
  };
  bool PropagateColumns(const ExactRecorder& recorder, int samples_per_cycle,
                        const Eigen::MatrixXd& basis, const std::atomic<bool>* cancel);
  void Extrema(Statistic& st, OutputStatistics& out, double cycle_start, bool want_min, int live);
  void Accumulate(const Statistic& st, OutputStatistics& out, int live);

  const SegmentTables& t_;
  const ConstantContactCycle& cycle_;
  bool usable_ = false, entered_ = false;
  int columns_ = 0;             // K_max + 1 (column 0: the orbit)
  Eigen::VectorXd orbit_;       // y*, refined (see the constructor)
  Eigen::MatrixXd modal_rows_;  // (K_max - 3) x m: q = V^-1 L (z - y*) (amplitudes at Enter)
  Eigen::MatrixXd projection_;  // Q^T L (V = Q R): the live coordinates y_K = (Q^T L)_K (z - y*)
  std::vector<int> amplitude_end_;      // per eigenvalue (a pair once): one past its rows
  std::vector<double> mode_decay_;      // its |lambda|
  std::vector<double> mode_tolerance_;  // how far |lambda| may be from the Schur block's modulus
  std::vector<int> block_start_;        // per Schur block: its first column
  std::vector<double> block_decay_;     // its |lambda|
  std::vector<double> tail_weight_;     // W_i of the columns from block i on
  std::vector<long> tail_last_;         // last cycle in which the tail from block i is alive
  size_t tail_block_ = 0;               // the first dead tail (block count: none)
  int live_ = 0;
  std::vector<Chunk> chunks_;
  std::vector<int> sample_chunk_;   // per sample of a cycle
  Eigen::MatrixXd samples_;         // (6 P) x (K_max + 1)
  std::array<Statistic, 3> stats_;  // te, mesh force, wheel acceleration
  double cycle_length_ = 0.0;
  std::vector<char> candidate_;  // per chunk, during Extrema
  Eigen::VectorXd x_, d_, values_, poly_;
};

}  // namespace gearnvh
