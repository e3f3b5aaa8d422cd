// Largest Lyapunov exponent of the exact piecewise-linear gear dynamics (docs/design.md §5).
//
// Benettin's method on the exact tangent dynamics: one tangent vector u (zero in the constant and
// excitation slots) is advanced with the state by the same segment propagators, saltation matrices
// at state-triggered contact changes and the identity at time-triggered ones (ExactStepper::
// AttachTangent). Every `renormalise_cycles` mesh cycles
//   g_i = ln |u|,  u <- u / |u|
// after `alignment_cycles` unaveraged cycles, with |.| the Euclidean norm of the elastic block [x;
// x'] on the quotient by the pair's free rotation (that rotation is neutral and changes no gap or
// force, so it is projected out; its multiplier 1 would otherwise hide every negative exponent).
// Then
//   lambda = sum_i g_i / T  (1/s, T the averaged time),
// reported per second, per mesh cycle (lambda T_m) and per rattle cycle (lambda T_f, T_f the period
// of the first engine order 2 pi / (order Omega1); the mesh period without excitation).
// Convergence: the run is cut into `blocks` equal blocks; the standard error is the standard
// deviation of the block exponents over sqrt(blocks).
// Predictability horizon: a state error at rounding (relative 2^-52) grows as e^{lambda t} and
// reaches the size of the state after t_p = 52 ln 2 / lambda; past t_p two runs can only be
// compared by their statistics, not their trajectories.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "gearnvh/solver/exact_solver.h"

namespace gearnvh {

struct LyapunovOptions {
  long transient_cycles = 500;  // mesh cycles run before the tangent starts; >= 0
  // Mesh cycles the tangent runs (renormalised) before averaging, so it has aligned with the most
  // unstable direction: without them the start direction biases lambda by O(1 / T). >= 0
  long alignment_cycles = 100;
  long cycles = 2000;           // mesh cycles averaged; >= blocks * renormalise_cycles
  long renormalise_cycles = 1;  // mesh cycles between renormalisations; >= 1
  int blocks = 8;               // blocks for the standard error; >= 2
  bool record = false;          // keep the trajectory of the averaged cycles (rattle indices)
  // Event method and memory bounds; method, cycles and transient_cycles are ignored (the tangent
  // needs every segment stepped).
  SolverOptions solver;
  void Validate() const;  // throws InputError naming the field
};

struct LyapunovEstimate {
  enum class Info { kSuccess, kSolverFailed };
  Info info = Info::kSuccess;
  std::string message;
  double exponent = 0.0;                // 1/s
  double per_mesh_cycle = 0.0;          // lambda T_m
  double per_forcing_cycle = 0.0;       // lambda T_f
  double forcing_period = 0.0;          // T_f, s
  double standard_error = 0.0;          // 1/s
  std::vector<double> block_exponents;  // 1/s
  // t_p = ln(2^52) / lambda (s) and in forcing cycles; infinity when lambda <= 0.
  double predictability_horizon_s = 0.0;
  double predictability_horizon_cycles = 0.0;
  SolverResult run;  // summary of the averaged cycles, and their trajectory when recorded
};
const char* LyapunovInfoName(LyapunovEstimate::Info info);

// Forcing (rattle) period T_f of the tables: 2 pi / (order_1 Omega1), or the mesh period.
double ForcingPeriod(const SegmentTables& tables);

LyapunovEstimate EstimateLyapunov(const SegmentTables& tables, const Eigen::VectorXd& z0,
                                  ContactState state0, const LyapunovOptions& options);

}  // namespace gearnvh
