// Segment-run fusion (docs/design.md §4.5): products of 2^l consecutive segment propagators in one
// contact state, used when a certificate proves that no wall can be reached over the run.
//
// For a run of segments k = j .. j + r - 1 (aligned: j a multiple of r, r = 2^l, l >= 1) the
// stepping loop sets the input slots to u_k at each segment start and applies Phi_k. With
// Pi = I - sum_q e_q e_q^T (clears the input slots) that is affine in z and in the u_k:
//   z_end = P z + sum_i U_i u_i,   P = Phi_{j+r-1} Pi ... Phi_j Pi,   U_i (m x p) the images of the
//   input slots set at segment i (so the run reproduces the step-by-step products exactly, up to
//   the order of rounding).
// Certificate, per wall the state can reach (event when sigma * g(t) rises above 0, g = c z with
// c = c_dyn + e_k on the constant slot for segment k): with h(t) = sigma c_dyn z(t) (continuous,
// with a continuous rate: c_dyn sees positions only),
//   h(t) <= h(0) + |h'(0)| t + 1/2 M2 t^2,   M2 >= sup |h''|,
// and no wall is reached when h(0) + |h'(0)| D + 1/2 M2 D^2 + max_k sigma e_k < -tol over the run
// duration D. M2 is bounded from precomputed weights: on the sub-step grid of the run,
//   W = max_t |c_dyn A_k^2 F(t)| (elementwise; F(t) the map from the run start),
//   W_q = max_t sum_i |c_dyn A_k^2 G_iq(t)| (the terms of input q),
// M2 = 4/3 (C_eq + W . |L Pi z - y_eq| + sum_q W_q u_q,max) with C_eq = max_t |c_dyn A_k^2 F(t)
// y_eq| for a reference state y_eq (the static equilibrium of the run's first segment; the
// constant slot alone in free flight), L removing the pair's free rotation (annihilated by these
// rows), u_q,max the bound of input q (SegmentTables::InputBound), and the factor 4/3 for the
// curvature between grid points (spacing d with rho d <= 1/2: |h''| exceeds its grid values by at
// most rho d / 2 of its maximum). The stepper checks the end state as well (inside its walls) and
// steps the run normally otherwise.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <vector>

#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

struct SegmentRun {
  int start = 0, length = 0;  // segments [start, start + length)
  double duration = 0.0;      // s
  Eigen::MatrixXd product;    // P (applied to z with the input slots cleared)
  Eigen::MatrixXd inputs;     // m x (length p): column i p + q is input q set at segment i
  struct Wall {
    double sign = 1.0;
    Eigen::RowVectorXd position_row, rate_row;  // sigma c_dyn, sigma c_dyn A_start
    Eigen::VectorXd curvature_weights;          // W
    Eigen::VectorXd input_weights;              // W_q
    // The run's reference state y_eq (static equilibrium of its first segment in contact; the
    // constant slot alone in free flight) and max_t |c_dyn A_k^2 F(t) y_eq| on the grid: the bound
    // is applied to the deviation from it, so the large static terms keep their cancellation.
    Eigen::VectorXd reference;
    double reference_curvature = 0.0;
    double constant_max = 0.0;  // max_k sigma e_k (the constant-slot terms)
  };
  std::vector<Wall> walls;
};

class SegmentRunTable {
 public:
  SegmentRunTable() = default;
  // Runs of 2, 4, ..., 2^max_level segments in `state`, aligned, for every start, built here;
  // `cancel` (SolverOptions::cancel) is polled per segment and per run built.
  SegmentRunTable(const SegmentTables& tables, ContactState state, int max_level,
                  const std::atomic<bool>* cancel = nullptr);
  // The longest run starting at `segment` that is certified for z (at that segment's start), or
  // nullptr. `scratch` has m entries. Does not allocate.
  const SegmentRun* Certify(int segment, const Eigen::VectorXd& z, Eigen::VectorXd& scratch);
  size_t bytes() const;  // of the runs built so far

 private:
  // The run of 2^level segments starting at segment index * 2^level (built by the constructor).
  const SegmentRun& Run(int level, int index) const;
  // Builds that run; the level below is built. grid[k]: the sub-step propagators of segment k.
  void Build(int level, int index, const std::vector<std::vector<Eigen::MatrixXd>>& grid);
  const SegmentTables* t_ = nullptr;
  ContactState state_ = ContactState::kFree;
  // runs_[level - 1][start / 2^level].
  std::vector<std::vector<SegmentRun>> runs_;
  size_t bytes_ = 0;
  double tolerance_ = 0.0;
  Eigen::VectorXd input_bounds_;  // u_q,max
};

}  // namespace gearnvh
