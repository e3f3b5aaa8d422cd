// Tangent propagation along an exact train run (docs/design.md §11, docs/gear-trains.md).
//
// The columns of V (m x k, zero in the constant and input slots) carry the derivative of the
// train's state z = [x; x'; 1; q; u] with respect to the initial state. TrainStepper advances them
// by the same maps that move the state (TrainStepper::AttachTangent):
//   a piece of length tau on a spectral tuple     V <- S e^{D tau} S^-1 V  (the state's closed
//   form) a piece on the dense (Taylor) path            V <- expm(A tau) V, Taylor with rho(A) tau
//   <= 1/2 a state-triggered event of mesh i             V <- (I + (f+ - f-) n_i^T / (n_i^T f-)) V
//     (saltation; n_i = [v_i; 0; 0; 0] the gap row of mesh i on z, f-/f+ the vector fields of the
//      tuples before and after the switch at the event state; they differ only in mesh i's force
//      F = k (v_i^T x - wall) + c v_i^T x' (0 when free): f+ - f- = [0; M^-1 u_ij (F- - F+); 0; 0]
//      with u_ij the flank's force direction (v_i, or v_i +- mu w_ij with friction),
//      and n_i^T f- = v_i^T x' is the gap rate, nonzero at a transversal crossing)
//   simultaneous events                           the saltations in the order the meshes switch
//     (they commute: n_j^T (f+ - f-)_i = 0, the jump is in the velocity rows only)
//   a grazing touch (state kept) and a time-triggered switch at a grid segment start (the wall
//     moved because e_ij jumped)                  nothing (I)
//   a recentring of the free rotation             V.x <- V.x - r (r^T M V.x)  (its derivative)
// The free rotation ([r; 0] with multiplier 1 and [0; r] -> [t r; r]) is neutral in every tuple:
// K_s r = C_s r = 0 and v_i^T r = 0. RemoveFreeRotation() projects it out (position and velocity,
// M-orthogonally). The rotation's span is invariant under every map above, so projecting after
// them gives the quotient's tangent; without friction the complement is invariant too (with
// friction r^T u_ij != 0 feeds the rotation's velocity, which the next projection removes).
// Attach() allocates the workspace; every other call is allocation-free.
#pragma once

#include <Eigen/Dense>

#include "gearnvh/solver/spectral_gap.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

class TrainTangentPropagator {
 public:
  // Terms of the Taylor series of expm(A tau) with rho(A) tau <= 1/2: (1/2)^18 / 18! ~ 1e-21.
  static constexpr int kTaylorTerms = 18;

  explicit TrainTangentPropagator(const TrainTables& tables) : t_(tables) {}
  // Attaches the columns (m rows, not owned); nullptr detaches. Allocates the workspace.
  void Attach(Eigen::MatrixXd* tangent);
  bool active() const { return v_ != nullptr; }

  void PropagateDecoupled(const SpectralDecomposition& d, double step);
  void PropagateTaylor(const Eigen::MatrixXd& A, double step);
  // Saltation of an event of `mesh` in grid segment `segment` at state z, from -> to.
  void Saltation(int mesh, int segment, ContactState from, ContactState to,
                 const Eigen::VectorXd& z);
  // The derivative of TrainStepper's recentring (x <- x - r r~ x).
  void Recenter();
  long saltations() const { return saltations_; }

 private:
  // Mesh force of `mesh` in `state` at z (0 when free), N.
  double MeshForce(int mesh, int segment, ContactState state, const Eigen::VectorXd& z) const;
  const TrainTables& t_;
  Eigen::MatrixXd* v_ = nullptr;
  Eigen::MatrixXd next_, work_;
  Eigen::VectorXd column_, wt_, scratch_;
  long saltations_ = 0;
};

// Removes the free rotation's position and velocity and every standing rotation's (the neutral
// directions, TrainTables::NeutralBasis, and the rotation's speed also when a viscous drag damps
// it) from the columns (M-orthogonal projection) and clears the constant and input slots.
void RemoveTrainFreeRotation(const TrainTables& tables, Eigen::Ref<Eigen::MatrixXd> V);

}  // namespace gearnvh
