#include "gearnvh/solver/train_tangents.h"

#include <stdexcept>

namespace gearnvh {

void TrainTangentPropagator::Attach(Eigen::MatrixXd* tangent) {
  v_ = tangent;
  if (tangent == nullptr) return;
  if (tangent->rows() != t_.m) {
    throw std::invalid_argument("TrainTangentPropagator::Attach: the tangent needs m rows");
  }
  next_.resize(t_.m, tangent->cols());
  work_.resize(t_.m, tangent->cols());
  column_.resize(t_.m);
  wt_.resize(t_.m);
  scratch_.resize(t_.m);
}

void TrainTangentPropagator::PropagateDecoupled(const SpectralDecomposition& d, double step) {
  work_.noalias() = d.S_inv * *v_;
  for (Eigen::Index c = 0; c < v_->cols(); ++c) {
    column_ = work_.col(c);
    gearnvh::PropagateDecoupled(d, column_, step, wt_, scratch_);
    work_.col(c) = wt_;
  }
  v_->noalias() = d.S * work_;
  // The decomposition leaks rounding into the constant and input slots; a tangent entry there
  // would act as a neutral forcing perturbation.
  v_->bottomRows(t_.m - 2 * t_.n).setZero();
}

void TrainTangentPropagator::PropagateTaylor(const Eigen::MatrixXd& A, double step) {
  // expm(A step) V by Horner: V + A step (V + A step / 2 (V + ...)).
  work_ = *v_;
  for (int k = kTaylorTerms; k >= 1; --k) {
    next_.noalias() = A * work_;
    work_ = *v_ + (step / static_cast<double>(k)) * next_;
  }
  v_->swap(work_);
  v_->bottomRows(t_.m - 2 * t_.n).setZero();
}

double TrainTangentPropagator::MeshForce(int mesh, int segment, ContactState state,
                                         const Eigen::VectorXd& z) const {
  if (state == ContactState::kFree) return 0.0;
  const TrainMeshTable& mt = t_.meshes[static_cast<size_t>(mesh)];
  const bool drive = state == ContactState::kDrive;
  const size_t j = static_cast<size_t>(segment);
  const double k = drive ? mt.k_drive[j] : mt.k_back[j];
  const double gap = t_.GapValue(mesh, segment, drive, z);
  return k * gap + mt.damping * mt.Vector(drive).dot(z.segment(t_.n, t_.n));
}

void TrainTangentPropagator::Saltation(int mesh, int segment, ContactState from, ContactState to,
                                       const Eigen::VectorXd& z) {
  const TrainMeshTable& mt = t_.meshes[static_cast<size_t>(mesh)];
  const int n = t_.n;
  // The gap that switched and the flank whose force jumps: drive unless the back flank is in it.
  const bool drive = from == ContactState::kDrive || to == ContactState::kDrive;
  const Eigen::VectorXd& v = mt.Vector(drive);
  const Eigen::VectorXd& u = mt.ForceVector(segment, drive);  // the force's direction (friction)
  const double rate = v.dot(z.segment(n, n));                 // n^T f-
  const double jump = MeshForce(mesh, segment, from, z) - MeshForce(mesh, segment, to, z);
  // V <- V + [0; M^-1 u_ij jump] (v_i^T V.x) / rate.
  for (Eigen::Index c = 0; c < v_->cols(); ++c) {
    const double along = v.dot(v_->col(c).head(n)) * jump / rate;
    v_->col(c).segment(n, n) += along * u.cwiseQuotient(t_.inertia);
  }
  ++saltations_;
}

void TrainTangentPropagator::Recenter() {
  for (Eigen::Index c = 0; c < v_->cols(); ++c) {
    const double drift = t_.recenter_row.dot(v_->col(c).head(t_.n));
    v_->col(c).head(t_.n) -= drift * t_.rigid_rotation;
  }
}

void RemoveTrainFreeRotation(const TrainTables& t, Eigen::Ref<Eigen::MatrixXd> V) {
  const int e = 2 * t.n;
  Eigen::MatrixXd U = t.NeutralBasis();
  if (t.free_rotation_damped) {
    // The rotation's speed too: it decays at r^T C r (a drag's sigma, often ~1e-3 1/s), which
    // would hide every exponent of the motion relative to it as the neutral pair would; removed,
    // the rest are the relative motion's to second order in the drag's coupling.
    U.conservativeResize(Eigen::NoChange, U.cols() + 1);
    U.col(U.cols() - 1).setZero();
    U.col(U.cols() - 1).tail(t.n) = t.rigid_rotation;
  }
  Eigen::VectorXd w(e);
  w << t.inertia, t.inertia;
  V.topRows(e) -= U * ((w.asDiagonal() * U).transpose() * V.topRows(e));
  V.bottomRows(t.m - e).setZero();
}

}  // namespace gearnvh
