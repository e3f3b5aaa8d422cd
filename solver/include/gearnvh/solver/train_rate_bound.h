// The dense path's bound rho on the spectral radius of one contact tuple's generator A_sigma
// (train_tables.h): TrainSystem::substep = min(1/2 / rho, kMaxDenseStepNorm / rate). The table
// cache and the app's slow-run estimate both take rho from BoundTupleRate, so the warning follows
// the solver whenever the bound changes.
//
// An eigenvalue lambda of A (eigenvector [u; lambda u], y = M^1/2 u, |y| = 1) solves
// lambda^2 + c lambda + k = 0 with c = y^* M^-1/2 C M^-1/2 y and k likewise: real in
// [0, lambda_max] for symmetric C, K >= 0, so |lambda| <= max(sqrt(k_max), c_max). C's skew part
// (gyroscopic, reduced tiers) and friction's rank-one terms make c and k complex; then
// |lambda| <= |c| + sqrt(|k|) (|lambda| = R > |c| + sqrt|k| gives R^2 - |c| R > |k|, which
// |lambda^2| = |c lambda + k| forbids), with |c| bounded by the symmetric part's lambda_max plus
// the skew part's norm (DampingRateBound) plus sum mu c_i |M^-1/2 w| |M^-1/2 v| (each friction term
// is c (y^* M^-1/2 mu w)(v^T M^-1/2 y)), and |k| likewise.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

// The second-order terms of one tuple (train_tables.h): K_s and C_s as their symmetric parts
// (the structure's K_0, C_0 plus sum k v v^T, sum c v v^T over the meshes in contact) and
// friction's rank-one parts sum k (u - v) v^T, sum c (u - v) v^T, kept apart for the bound.
struct TuplePencil {
  Eigen::MatrixXd K, C;                    // n x n
  Eigen::VectorXd force;                   // f_s, N m
  Eigen::MatrixXd friction_k, friction_c;  // empty when no mesh in contact has friction
  // sum k_ij |M^-1/2 (u_ij - v_i)| |M^-1/2 v_i| over the meshes in contact, and with c_i.
  double friction_k_norm = 0.0, friction_c_norm = 0.0;
};
TuplePencil AssembleTuplePencil(const TrainTables& tables, const std::vector<int>& segments,
                                const std::vector<ContactState>& states);

// The bound on |c| from the damping C (a pencil's C): lambda_max(M^-1 C), or with a skew
// structural C_0 that of the symmetric part plus the skew part's norm. It depends on the contact
// states only (c_i is constant per mesh), so the table cache keeps it per state combination.
double DampingRateBound(const TrainTables& tables, const Eigen::MatrixXd& C);
// The skew part's share of DampingRateBound: |M^-1/2 (C_0 - C_0^T)/2 M^-1/2| (the gyroscopic
// term of a reduced tier), 0 when C_0 is symmetric.
double GyroscopicRateBound(const TrainTables& tables);

struct TupleRateBound {
  double rho = 0.0;  // >= |lambda| for every eigenvalue of A_sigma, 1/s
  // sqrt(lambda_max(M^-1 K_sym)), the highest frictionless undamped mode, rad/s (also the scale
  // of the decomposition's velocity balance).
  double stiffness_frequency = 0.0;
  // Friction's share of rho: sqrt(w^2 + friction_k_norm) - w + friction_c_norm (0 without).
  double friction_rate = 0.0;
};
// From a tuple's pencil and its DampingRateBound.
TupleRateBound BoundTupleRate(const TrainTables& tables, const TuplePencil& pencil,
                              double damping_rate);

}  // namespace gearnvh
