// Constant-contact regime: a mesh cycle as one matrix, its periodic orbit and certified jumps
// (docs/design.md §4.3).
//
// In one contact state sigma, with no engine excitation, the cycle map is the product of the
// segment propagators, P = Phi_S ... Phi_1 (affine in the augmented state: P = [[P_xx, p], [0,
// 1]]). The pair's free rotation spans an invariant subspace R = span{[r; 0], [0; r]} on which no
// gap and no force depends (P [r;0] = [r;0], P [0;r] = [0;r] + T [r;0]); P therefore has the
// eigenvalue 1 there. All fixed-point and jump algebra runs on the quotient by R with the projector
//   L = I - [r;0][r~;0]^T - [0;r][0;r~]^T,  r~ = M r (r~^T r = 1),
// and the rigid velocity is carried along unchanged (rigid positions are recentred anyway):
//   periodic orbit   (I - L P L + (I - L)) y = L p-part   (B is nonsingular when the elastic
//                    part of P has no multiplier 1),
//   k cycles ahead   L z_k = y* + (L P L)^k (L z_0 - y*)   via binary powers (popcount(k) matvecs),
//                    and the rigid velocity, which gains rho (P - I) L z_i per cycle (dynamic
//                    friction), v_k = v_0 + k rho y* + rho (I - Pq)^-1 (delta_0 - delta_k)   in
//                    closed form.
// Certificate (permanent contact for all future cycles): expand the deviation in the eigenvectors
// of the quotient map, L z_0 - y* = sum_i a_i phi_i; in cycle k at grid time t the gap changes by
// sum_i a_i lambda_i^k (c Phi(t) phi_i), so with every visible |lambda_i| <= 1
//   |gap change| <= sum_i |a_i| max_t |c Phi(t) phi_i|   for all k >= 0.
// Certified when that bound (plus 1 %) stays below the orbit's smallest contact margin over the
// sub-step grid minus a curvature slack (1/8) max|g''| D^2 between grid points. Modes the gap
// cannot see (undamped tilt, say) do not count; a visible growing mode or a defective eigenbasis
// refuses.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <complex>
#include <string>
#include <vector>

#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

struct ContactCertificate {
  bool certified = false;
  std::string reason;            // why not, when not certified
  double orbit_margin = 0.0;     // m: smallest gap of the periodic orbit (minus curvature slack)
  double deviation_bound = 0.0;  // m: largest gap change the transient can cause
};

class ConstantContactCycle {
 public:
  // Tables must have no engine excitation; `state` is kDrive or kBack. `cancel`
  // (SolverOptions::cancel) is polled per segment of the build.
  ConstantContactCycle(const SegmentTables& tables, ContactState state,
                       const std::atomic<bool>* cancel = nullptr, int max_jump_log2 = 40);

  const Eigen::MatrixXd& map() const { return P_; }        // one matvec per cycle
  const Eigen::VectorXd& orbit() const { return orbit_; }  // y*, on the quotient (cycle start)
  bool has_orbit() const { return has_orbit_; }
  // State after k whole cycles from z0 (exact affine algebra on the quotient; rigid velocity kept).
  Eigen::VectorXd Jump(const Eigen::VectorXd& z0, long long cycles) const;
  // Whether contact is kept forever from z0 (at a cycle start).
  ContactCertificate Certify(const Eigen::VectorXd& z0) const;
  ContactState state() const { return state_; }
  // The quotient map's elastic block Pq = (L P L)[0:2n, 0:2n]: eigenvalues and eigenvectors
  // (empty without an orbit), and the projector L itself.
  const Eigen::VectorXcd& eigenvalues() const { return eigenvalues_; }
  const Eigen::MatrixXcd& eigenvectors() const { return eigenvectors_; }
  const Eigen::MatrixXd& projector() const { return L_; }

 private:
  Eigen::VectorXd Project(const Eigen::VectorXd& z) const;  // L z
  const SegmentTables& t_;
  ContactState state_;
  Eigen::MatrixXd P_, Pq_, L_;
  std::vector<Eigen::MatrixXd> powers_;  // (L P L)^(2^l)
  Eigen::VectorXd orbit_;
  bool has_orbit_ = false;
  double orbit_margin_ = 0.0;
  Eigen::RowVectorXd velocity_row_;      // rho (P - I) L
  double velocity_drift_ = 0.0;          // rigid velocity gained per cycle on the orbit
  Eigen::RowVectorXd velocity_sum_row_;  // rho (I - Pq)^-1 on the elastic block
  Eigen::VectorXcd eigenvalues_;
  Eigen::MatrixXcd eigenvectors_;
  Eigen::FullPivLU<Eigen::MatrixXcd> modal_lu_;
  Eigen::VectorXd mode_gap_gain_;  // max over the grid of |c Phi(t) phi_i|
};

}  // namespace gearnvh
