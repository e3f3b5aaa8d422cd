#include "gearnvh/solver/tangent_propagator.h"

#include <stdexcept>

namespace gearnvh {

void TangentPropagator::Attach(Eigen::MatrixXd* tangent) {
  v_ = tangent;
  if (tangent == nullptr) return;
  if (tangent->rows() != t_.m) {
    throw std::invalid_argument("TangentPropagator::Attach: the tangent needs m rows");
  }
  next_.resize(t_.m, tangent->cols());
  work_.resize(t_.m, tangent->cols());
  f_minus_.resize(t_.m);
  f_plus_.resize(t_.m);
  column_.resize(t_.m);
  wt_.resize(t_.m);
  scratch_.resize(t_.m);
}

void TangentPropagator::Propagate(const Eigen::MatrixXd& propagator) {
  next_.noalias() = propagator * *v_;
  v_->swap(next_);
}

void TangentPropagator::PropagateTaylor(const Eigen::MatrixXd& A, double step) {
  // expm(A step) V = V + A step (V + A step / 2 (V + ...)) (Horner); rho(A) step <= 1/2 here, so
  // kTaylorTerms terms reach rounding as for the state.
  work_ = *v_;
  for (int k = kTaylorTerms; k >= 1; --k) {
    next_.noalias() = A * work_;
    work_ = *v_ + (step / static_cast<double>(k)) * next_;
  }
  v_->swap(work_);
}

void TangentPropagator::PropagateDecoupled(const SpectralDecomposition& d, double step) {
  work_.noalias() = d.S_inv * *v_;
  for (Eigen::Index c = 0; c < v_->cols(); ++c) {
    column_ = work_.col(c);
    gearnvh::PropagateDecoupled(d, column_, step, wt_, scratch_);
    work_.col(c) = wt_;
  }
  v_->noalias() = d.S * work_;
  // The decomposition leaks rounding into the constant and input slots; a tangent entry there
  // would act as a neutral (multiplier-1) forcing perturbation and pin the exponent at 0.
  v_->bottomRows(1 + t_.inputs).setZero();
}

void TangentPropagator::Saltation(const Eigen::MatrixXd& A_from, const Eigen::MatrixXd& A_to,
                                  const Eigen::RowVectorXd& row, const Eigen::VectorXd& z) {
  // V <- V + (f+ - f-) (n^T V) / (n^T f-); n^T f- is the gap rate.
  f_minus_.noalias() = A_from * z;
  f_plus_.noalias() = A_to * z;
  f_plus_ -= f_minus_;
  const double denominator = row.dot(f_minus_);
  for (Eigen::Index c = 0; c < v_->cols(); ++c) {
    const double along = row.dot(v_->col(c)) / denominator;
    v_->col(c) += along * f_plus_;
  }
}

void TangentPropagator::EndCycle() {
  RemoveFreeRotation(t_, *v_);
  v_->bottomRows(1 + t_.inputs).setZero();
}

}  // namespace gearnvh
