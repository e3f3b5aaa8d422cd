#include "gearnvh/solver/cycle_map.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "flush_subnormals.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh {

ConstantContactCycle::ConstantContactCycle(const SegmentTables& t, ContactState state,
                                           const std::atomic<bool>* cancel, int max_jump_log2)
    : t_(t), state_(state) {
  const int m = t.m, n = t.n;
  const int s = static_cast<int>(state);
  P_ = Eigen::MatrixXd::Identity(m, m);
  for (int j = 0; j < t.segments(); ++j) {
    ThrowIfCancelled(cancel);
    P_ = (t.systems[j][s].full * P_).eval();
  }
  // Quotient projector removing the free-rotation subspace (position and velocity parts).
  L_ = FreeRotationProjector(t);
  Pq_ = L_ * P_ * L_;
  // Fixed point: the elastic block only (the constant and excitation slots stay 1 and 0).
  const int e = 2 * n;
  const Eigen::MatrixXd Le = L_.topLeftCorner(e, e);
  const Eigen::MatrixXd B = Eigen::MatrixXd::Identity(e, e) - Pq_.topLeftCorner(e, e) +
                            (Eigen::MatrixXd::Identity(e, e) - Le);
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(B);
  has_orbit_ = lu.isInvertible();
  orbit_ = Eigen::VectorXd::Zero(m);
  orbit_[2 * n] = 1.0;
  if (has_orbit_) orbit_.head(e) = lu.solve(Pq_.block(0, 2 * n, e, 1));
  // Rigid velocity per cycle: v_{k+1} - v_k = rho (P - I) L z_k (the free rotation itself adds
  // nothing); rho measures the rigid velocity.
  Eigen::RowVectorXd rho = Eigen::RowVectorXd::Zero(m);
  rho.segment(n, n) = t.recenter_row;
  velocity_row_ = rho * (P_ - Eigen::MatrixXd::Identity(m, m)) * L_;
  if (has_orbit_) {
    velocity_drift_ = velocity_row_.dot(orbit_);
    velocity_sum_row_ = velocity_row_.head(e) * lu.inverse();  // rho (I - Pq)^-1 on range(L)
  }
  powers_.push_back(Pq_);
  for (int l = 1; l < max_jump_log2; ++l) {
    powers_.push_back(powers_.back() * powers_.back());
    internal::FlushSubnormals(powers_.back());
  }

  // Orbit margin over the sub-step grid of one cycle, and the grid rows c Phi(t) L (elastic block).
  if (!has_orbit_) return;
  Eigen::VectorXd z = orbit_;
  Eigen::MatrixXd Phi = Eigen::MatrixXd::Identity(m, m);  // from the cycle start
  std::vector<Eigen::RowVectorXd> rows;
  orbit_margin_ = 1e300;
  double curvature = 0.0, substep2 = 0.0;
  for (int j = 0; j < t.segments(); ++j) {
    ThrowIfCancelled(cancel);
    const SegmentSystem& sys = t.systems[j][s];
    const Eigen::RowVectorXd& c = state == ContactState::kDrive ? sys.gap_drive : sys.gap_back;
    const double sign = state == ContactState::kDrive ? 1.0 : -1.0;  // margin = sign * gap
    const Eigen::RowVectorXd c2 = c * sys.A * sys.A;
    const double d = t.SegmentLength(j) / t.substeps[j];
    substep2 = std::max(substep2, d * d);
    for (int i = 0; i <= t.substeps[j]; ++i) {
      orbit_margin_ = std::min(orbit_margin_, sign * c.dot(z));
      curvature = std::max(curvature, std::abs(c2.dot(z)));
      rows.push_back((c * Phi * L_).head(e));
      if (i < t.substeps[j]) {
        z = sys.substep * z;
        Phi = sys.substep * Phi;
      }
    }
  }
  // Between grid points the gap can dip below the chord by at most (1/8) max|g''| D^2; doubled.
  orbit_margin_ -= 0.25 * curvature * substep2;
  // Modal decomposition of the quotient map's elastic block: deviation = sum a_i phi_i, and the gap
  // change in any later cycle at grid time t is sum a_i lambda_i^k (c Phi(t) phi_i).
  const Eigen::EigenSolver<Eigen::MatrixXd> eig(Pq_.topLeftCorner(e, e));
  eigenvalues_ = eig.eigenvalues();
  eigenvectors_ = eig.eigenvectors();
  modal_lu_ = Eigen::FullPivLU<Eigen::MatrixXcd>(eigenvectors_);
  mode_gap_gain_ = Eigen::VectorXd::Zero(e);
  for (const Eigen::RowVectorXd& row : rows) {
    const Eigen::RowVectorXcd g = row.cast<std::complex<double>>() * eigenvectors_;
    for (int i = 0; i < e; ++i) mode_gap_gain_[i] = std::max(mode_gap_gain_[i], std::abs(g[i]));
  }
}

Eigen::VectorXd ConstantContactCycle::Project(const Eigen::VectorXd& z) const { return L_ * z; }

Eigen::VectorXd ConstantContactCycle::Jump(const Eigen::VectorXd& z0, long long cycles) const {
  const int n = t_.n;
  Eigen::VectorXd dev = Project(z0) - orbit_;
  dev.tail(t_.m - 2 * n).setZero();  // the constant and input slots
  const Eigen::VectorXd initial = dev;
  const long long total = cycles;
  for (int l = 0; cycles > 0; ++l, cycles >>= 1) {
    if (l >= static_cast<int>(powers_.size())) throw std::out_of_range("cycle jump too long");
    if (cycles & 1) {
      dev = (powers_[l] * dev).eval();
      internal::FlushSubnormals(dev);
    }
  }
  Eigen::VectorXd z = orbit_ + dev;
  // The free rotation's velocity changes by rho (P - I) L z_i each cycle: summed in closed form,
  //   v_k = v_0 + k rho y* + rho (I - Pq)^-1 (delta_0 - delta_k); its position is recentred.
  const double rigid_velocity = t_.recenter_row.dot(z0.segment(n, n)) +
                                static_cast<double>(total) * velocity_drift_ +
                                velocity_sum_row_.dot((initial - dev).head(2 * n));
  z.segment(n, n) += rigid_velocity * t_.rigid_rotation;
  return z;
}

ContactCertificate ConstantContactCycle::Certify(const Eigen::VectorXd& z0) const {
  ContactCertificate c;
  if (!has_orbit_) {
    c.reason = "the cycle map has no periodic orbit (a multiplier 1 besides the free rotation)";
    return c;
  }
  if (!modal_lu_.isInvertible()) {
    c.reason = "the cycle map's eigenvectors are not a basis (defective map)";
    return c;
  }
  const int e = 2 * t_.n;
  const Eigen::VectorXd dev = (Project(z0) - orbit_).head(e);
  const Eigen::VectorXcd a = modal_lu_.solve(dev.cast<std::complex<double>>());
  // Reject an ill-conditioned eigenbasis: the expansion must reproduce the deviation.
  if ((eigenvectors_ * a - dev.cast<std::complex<double>>()).norm() >
      1e-8 * (dev.norm() + 1e-300)) {
    c.reason = "the cycle map's eigenbasis is too ill-conditioned to bound the transient";
    return c;
  }
  double bound = 0.0;
  for (int i = 0; i < e; ++i) {
    const double weight = std::abs(a[i]) * mode_gap_gain_[i];
    if (weight == 0.0) continue;
    // Neutral modes (|lambda| = 1 to rounding: undamped tilt, say) keep the bound; a mode growing
    // by more than 1e-9 per cycle refuses unless its gap weight is negligible (1e-9 of the margin).
    if (std::abs(eigenvalues_[i]) > 1.0 + 1e-9 && weight > 1e-9 * std::abs(orbit_margin_)) {
      c.reason = "a growing mode of the cycle map is visible in the gap";
      return c;
    }
    bound += weight;
  }
  c.orbit_margin = orbit_margin_;
  c.deviation_bound = 1.01 * bound;  // 1 % for the deviation's own dip between grid points
  c.certified = orbit_margin_ > 0.0 && c.deviation_bound < orbit_margin_;
  if (!c.certified) c.reason = "the transient may reach the wall (deviation bound >= orbit margin)";
  return c;
}

}  // namespace gearnvh
