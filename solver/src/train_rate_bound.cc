// The dense path's spectral-radius bound of a contact tuple (train_rate_bound.h).
#include "gearnvh/solver/train_rate_bound.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gearnvh {
namespace {

// lambda_max(M^-1 X) from the symmetric M^-1/2 X M^-1/2 (same eigenvalues, cheaper), on the
// coordinates whose row of X is nonzero (the others add zero eigenvalues: at tier 1 the bodies no
// contact couples).
double LargestRate(const Eigen::VectorXd& inv_j, const Eigen::MatrixXd& X) {
  const Eigen::VectorXd root_inv_j = inv_j.cwiseSqrt();
  std::vector<int> rows;
  for (int j = 0; j < X.rows(); ++j) {
    if (!X.row(j).isZero(0.0)) rows.push_back(j);
  }
  if (rows.empty()) return 0.0;
  Eigen::MatrixXd sym;
  if (rows.size() == static_cast<size_t>(X.rows())) {
    sym = root_inv_j.asDiagonal() * X * root_inv_j.asDiagonal();
  } else {
    sym = root_inv_j(rows).asDiagonal() * X(rows, rows) * root_inv_j(rows).asDiagonal();
  }
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(sym, Eigen::EigenvaluesOnly)
      .eigenvalues()
      .cwiseAbs()
      .maxCoeff();
}

// Only the structure's C_0 + w G can be skew (the mesh terms are symmetric up to rounding of
// c v_i v_j, which must not switch tier 1 to the looser bound).
bool SkewDamping(const TrainTables& t) {
  const Eigen::MatrixXd& c0 = t.structural_damping;
  return c0.size() > 0 && !(0.5 * (c0 - c0.transpose())).isZero(0.0);
}

}  // namespace

TuplePencil AssembleTuplePencil(const TrainTables& t, const std::vector<int>& segments,
                                const std::vector<ContactState>& states) {
  const int n = t.n;
  TuplePencil p;
  p.K = t.structural_stiffness.size() > 0 ? t.structural_stiffness : Eigen::MatrixXd::Zero(n, n);
  p.C = t.structural_damping.size() > 0 ? t.structural_damping : Eigen::MatrixXd::Zero(n, n);
  p.force = t.force;
  const Eigen::VectorXd root_inv_j = t.inertia.cwiseInverse().cwiseSqrt();
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    if (states[i] == ContactState::kFree) continue;
    const TrainMeshTable& mt = t.meshes[i];
    const int j = segments[i];
    const bool drive = states[i] == ContactState::kDrive;
    const double e = mt.error[static_cast<size_t>(j)], b = mt.half_backlash;
    const double k = drive ? mt.k_drive[static_cast<size_t>(j)] : mt.k_back[static_cast<size_t>(j)];
    const Eigen::VectorXd& v = mt.Vector(drive);
    const Eigen::VectorXd& u = mt.ForceVector(j, drive);
    p.K += k * v * v.transpose();
    p.C += mt.damping * v * v.transpose();
    p.force += k * (drive ? e + b : e - b) * u;
    if (!mt.has_friction()) continue;
    if (p.friction_k.size() == 0) p.friction_k = p.friction_c = Eigen::MatrixXd::Zero(n, n);
    const Eigen::VectorXd slide = u - v;
    p.friction_k += k * slide * v.transpose();
    p.friction_c += mt.damping * slide * v.transpose();
    const double norms = root_inv_j.cwiseProduct(slide).norm() * root_inv_j.cwiseProduct(v).norm();
    p.friction_k_norm += k * norms;
    p.friction_c_norm += mt.damping * norms;
  }
  return p;
}

double GyroscopicRateBound(const TrainTables& t) {
  if (!SkewDamping(t)) return 0.0;
  const Eigen::MatrixXd& c0 = t.structural_damping;
  const Eigen::MatrixXd skew = 0.5 * (c0 - c0.transpose());
  const Eigen::VectorXd root_inv_j = t.inertia.cwiseInverse().cwiseSqrt();
  return (root_inv_j.asDiagonal() * skew * root_inv_j.asDiagonal()).norm();
}

double DampingRateBound(const TrainTables& t, const Eigen::MatrixXd& C) {
  const Eigen::VectorXd inv_j = t.inertia.cwiseInverse();
  if (!SkewDamping(t)) return LargestRate(inv_j, C);
  return LargestRate(inv_j, 0.5 * (C + C.transpose())) + GyroscopicRateBound(t);
}

TupleRateBound BoundTupleRate(const TrainTables& t, const TuplePencil& p, double damping_rate) {
  TupleRateBound out;
  out.stiffness_frequency = std::sqrt(LargestRate(t.inertia.cwiseInverse(), p.K));
  const double w = out.stiffness_frequency;
  if (p.friction_k.size() > 0) {
    const double stiffness = std::sqrt(w * w + p.friction_k_norm);
    out.rho = stiffness + damping_rate + p.friction_c_norm;
    out.friction_rate = stiffness - w + p.friction_c_norm;
  } else {
    out.rho = SkewDamping(t) ? w + damping_rate : std::max(w, damping_rate);
  }
  return out;
}

}  // namespace gearnvh
