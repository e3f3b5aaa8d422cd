// Tangent propagation along an exact piecewise-LTI run (docs/design.md §5).
//
// The columns of V (m x p, zero in the constant and input slots) carry the derivative of the state
// with respect to the initial state. They are advanced by the same maps as the state:
//   over a span of segment j in state sigma      V <- expm(A_{j,sigma} tau) V
//     (the dense propagator, its Taylor series for rho(A) tau <= 1/2, or the decoupled
//      exponential S e^{B tau} S^-1 of spectral_gap.h: whichever map moved the state);
//   at a state-triggered crossing of gap row n    V <- (I + (f+ - f-) n^T / (n^T f-)) V,
//     f-/f+ = A_from z / A_to z at the event (saltation; n^T f- = g', the gap rate, != 0);
//   at a time-triggered switch (a segment starts outside a wall because e_j jumped)   nothing (I);
//   at a grazing touch (state kept)               nothing;
//   at every cycle end                            V <- projection onto the quotient by the pair's
//     free rotation (FreeRotationProjector): its position and velocity are neutral (multiplier 1)
//     and change no gap or force.
// Attach() allocates the workspace; every other call is allocation-free.
#pragma once

#include <Eigen/Dense>

#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/spectral_gap.h"

namespace gearnvh {

class TangentPropagator {
 public:
  // Terms of the Taylor series of expm(A tau) with rho(A) tau <= 1/2: (1/2)^18 / 18! ~ 1e-21.
  static constexpr int kTaylorTerms = 18;

  explicit TangentPropagator(const SegmentTables& tables) : t_(tables) {}
  // Attaches the columns (m rows, not owned); nullptr detaches. Allocates the workspace.
  void Attach(Eigen::MatrixXd* tangent);
  bool active() const { return v_ != nullptr; }

  void Propagate(const Eigen::MatrixXd& propagator);            // V <- Phi V
  void PropagateTaylor(const Eigen::MatrixXd& A, double step);  // V <- expm(A step) V
  void PropagateDecoupled(const SpectralDecomposition& d, double step);
  // Saltation at a state-triggered crossing of `row` in state z (from generator A_from to A_to).
  void Saltation(const Eigen::MatrixXd& A_from, const Eigen::MatrixXd& A_to,
                 const Eigen::RowVectorXd& row, const Eigen::VectorXd& z);
  // Cycle end: project out the free rotation; clear the constant and input slots.
  void EndCycle();

 private:
  const SegmentTables& t_;
  Eigen::MatrixXd* v_ = nullptr;
  Eigen::MatrixXd next_, work_;
  Eigen::VectorXd f_minus_, f_plus_, column_, wt_, scratch_;
};

}  // namespace gearnvh
