// A gear train's constant-contact cycle map over its common period, its periodic orbit and
// certified jumps (docs/design.md §11, §4.3; docs/gear-trains.md "Certified jumps").
//
// Common period T_c (TrainTables::common_period): C_i = T_c / T_i whole cycles of every mesh and
// whole periods of every engine order, so with every mesh in one contact state sigma_i (drive or
// back; a coupling's stage may also stay free, its twist certified between both walls) the train
// is linear and T_c-periodic. Its grid segments g = 1..G of [0, T_c) (the union
// grid, TrainGrid) each have the generator A_g of their tuple and the inputs u_g (the engine
// orders' states at the grid segment's start, the errors' means over it), set as the stepper sets
// them: at the segment start every input slot s is set, z <- R_g z with R_g = I - sum_s e_s e_s^T
// + sum_s u_g,s e_s e_1^T (e_1 the constant slot), so
//   Phi = prod_g expm(A_g h_g) R_g   (m x m, affine through the constant slot),
// Phi^k z is the state after k common periods, bit for bit the maps the stepper applies up to
// rounding. (The pair refuses a cycle map with an engine order because one mesh cycle is not a
// period of the excitation; T_c is, by construction.)
// Quotient by the free rotation r (as the pair, cycle_map.h): L = I - [r;0][r~;0]^T -
// [0;r][0;r~]^T, Pq = L Phi L; orbit y* from (I - Pq + (I - L_e)) y = Pq e_1 on the elastic block
// 2n; then L z_k = y* + Pq^k (L z_0 - y*), and the rigid velocity gains rho (Phi - I) L z_k per
// period (rho = r~ on the velocities), summed in closed form:
//   v_K = v_0 + K rho (Phi - I) y* + rho (Phi - I) (I - Pq)^-1 (d_0 - d_K),  d_k = Pq^k d_0.
// Certificate (every future period keeps every mesh in its state): with spectral radius
// rho(Pq) < 1 (refused otherwise: the transient must contract) and d_0 = sum_i a_i phi_i in the
// eigenvectors of Pq, the gap of mesh j at time t of period k moves from the orbit's by
// sum_i a_i lambda_i^k c_j Phi(t) phi_i, at most B_j = sum_i |a_i| G_ji, G_ji = sup_t |c_j Phi(t)
// phi_i|. The orbit's margin M_j = inf_t sign_j g_j(t). Both are bounded over every sub-step of
// every grid segment (rho(A_g) d <= 1 and q = ||S A_g S^-1||_inf d <= 3 with S the balancing of
// BalancedExpm, the Taylor polynomial of the sub-step, 30 terms, its remainder bounded by ||c_j||_1
// ||S y||_inf e^q q^31 / 31! and added to every bound; the sub-step propagator is the map's own
// expm when d = h): on [0, d] with nodes tau_k = k d / 16, a C^2 function's minimum is >= min_k
// f(tau_k) - (d/16)^2 sup|f''| / 8 and the modulus of a complex one's maximum <= max_k |f(tau_k)| +
// the same, sup|f''| from the polynomial's coefficients (sum p (p-1) |f_p| d^(p-2)). Certified when
// B_j < (1 - margin_fraction) M_j for every mesh j. A jump of K periods: powers Pq^(2^l) (binary,
// subnormals flushed to zero). Cost: G expm and G sub-step walks once per contact combination (the
// period's distinct tuples assembled once each; its propagators kept during the build up to
// kKeepBytes); memory held (40 + 4) m^2 doubles plus the meshes' gains; built only when G <=
// TrainStepperOptions::max_cycle_map_segments.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <map>
#include <vector>

#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

// The grid segments of one common period, counted up to `limit`.
long CountCommonPeriodSegments(const TrainTables& tables, long limit);

class TrainCycleMap {
 public:
  enum class Info {
    kSuccess,
    kNoOrbit,         // I - Pq singular on the quotient (a multiplier 1 besides the rotation)
    kNotContracting,  // spectral radius of Pq >= 1
    kNoMargin,        // the orbit itself touches or crosses a wall
    kDefectiveBasis,  // the eigenvectors of Pq are not a usable basis
  };
  static constexpr int kMaxJumpLog2 = 40;  // jumps of up to 2^40 - 1 periods
  // Sub-steps d with q = ||S A S^-1|| d <= kMaxStepNorm; the Taylor tail e^q q^31 / 31! <= 2e-18.
  static constexpr int kTaylorTerms = 30;
  static constexpr double kMaxStepNorm = 3.0;

  // The map of one common period with every mesh in `states` (each kDrive or kBack);
  // margin_fraction in [0, 1) is the share of each orbit margin kept free of the transient;
  // grid_segments: the period's grid segments (sizes the kept propagators); `cancel`
  // (TrainStepperOptions::cancel) is polled per grid segment of the build.
  TrainCycleMap(const TrainTables& tables, const std::vector<ContactState>& states,
                double margin_fraction, long grid_segments,
                const std::atomic<bool>* cancel = nullptr);
  Info info() const { return info_; }
  const std::vector<ContactState>& states() const { return states_; }
  const Eigen::MatrixXd& map() const { return phi_; }
  const Eigen::VectorXd& orbit() const { return orbit_; }  // y*, at a common period's start
  double spectral_radius() const { return spectral_radius_; }
  // Per mesh: the orbit's margin M_j (m) and the transient's bound B_j from the last Certify.
  const Eigen::VectorXd& margins() const { return margin_; }
  const Eigen::VectorXd& deviation_bounds() const { return bound_; }
  size_t bytes() const;

  // Whether every mesh keeps its state forever from z (at a common period's start). No
  // allocation.
  bool Certify(const Eigen::VectorXd& z);
  // z <- the state `periods` common periods later (exact affine algebra; no allocation).
  void Jump(Eigen::VectorXd& z, long long periods);

 private:
  // Per tuple of the period (keyed by the meshes' segments; the states are fixed): its generator,
  // w_ref, spectral radius, and the gap rows c_j A^p, p = 0..kTaylorTerms (mesh-major).
  struct Tuple {
    Eigen::MatrixXd A, gap_powers;
    Eigen::VectorXd gap_norms;      // per mesh ||c_j||_1 (position rows: unchanged by balancing)
    double w_ref = 1.0, rho = 0.0;  // rho: spectral radius of A
    double rate = 0.0;              // ||S A S^-1||_inf, S = diag(1, 1 / w_ref, 1)
  };
  using TupleMemo = std::map<std::vector<int>, Tuple>;
  const Tuple& Lookup(TupleMemo& memo, const std::vector<int>& segments) const;
  // The period's propagators expm(A_g h_g) are kept for the certificate's walk up to this size.
  static constexpr double kKeepBytes = 64.0 * 1048576.0;
  void BuildMap(TupleMemo& memo, std::vector<Eigen::MatrixXd>& propagators, long grid_segments,
                const std::atomic<bool>* cancel);
  void BuildCertificate(TupleMemo& memo, const std::vector<Eigen::MatrixXd>& propagators,
                        const std::atomic<bool>* cancel);
  const TrainTables& t_;
  std::vector<ContactState> states_;
  double margin_fraction_;
  Info info_ = Info::kSuccess;
  Eigen::MatrixXd phi_, pq_, projector_;
  std::vector<Eigen::MatrixXd> powers_;  // Pq^(2^l)
  Eigen::VectorXd orbit_;
  Eigen::VectorXd standing_;  // Jump's scratch: each standing rotation's position and velocity
  // mv_: the row measuring the free rotation's velocity, zero when a drag damps it (the map then
  // carries it like any other coordinate).
  Eigen::RowVectorXd mv_, velocity_row_,
      velocity_sum_row_;                                // rho (Phi - I) L; and times (I - Pq)^-1
  double velocity_drift_ = 0.0;                         // rho (Phi - I) y*
  double spectral_radius_ = 0.0;
  Eigen::MatrixXcd eigenvectors_, eigenvectors_inv_;
  Eigen::MatrixXd gain_;  // meshes x 2n: G_ji
  Eigen::VectorXd margin_, bound_;
  // Scratch (no allocation in Certify and Jump).
  Eigen::VectorXd dev_, dev0_, next_;
  Eigen::VectorXcd dev_complex_, coeff_, rebuilt_;
};

}  // namespace gearnvh
