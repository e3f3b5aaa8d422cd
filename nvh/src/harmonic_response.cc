#include "gearnvh/nvh/harmonic_response.h"

#include <stdexcept>
#include <string>

namespace gearnvh {

void HarmonicModel::CheckSizes() const {
  const long n = M.rows();
  const auto square = [n](const Eigen::MatrixXd& a, const char* name) {
    if (a.rows() != n || a.cols() != n)
      throw std::invalid_argument(std::string("HarmonicModel.") + name + " must be n x n");
  };
  square(M, "M");
  square(C, "C");
  square(G, "G");
  square(K, "K");
  const size_t meshes = mesh_vectors.size();
  if (mesh_stiffness.size() != meshes || mesh_damping.size() != meshes)
    throw std::invalid_argument("HarmonicModel.mesh_stiffness/mesh_damping: one per mesh vector");
  for (const Eigen::VectorXd& v : mesh_vectors) {
    if (v.size() != n) throw std::invalid_argument("HarmonicModel.mesh_vectors must have n rows");
  }
  if (te_vectors.size() != meshes)
    throw std::invalid_argument("HarmonicModel.te_vectors: one per mesh vector");
  for (const Eigen::VectorXd& t : te_vectors) {
    if (t.size() != n) throw std::invalid_argument("HarmonicModel.te_vectors must have n rows");
  }
  if (bearing_stiffness.size() != bearing_damping.size())
    throw std::invalid_argument("HarmonicModel.bearing_damping: one per bearing");
  for (size_t b = 0; b < bearing_stiffness.size(); ++b) {
    for (const Eigen::MatrixXd* a : {&bearing_stiffness[b], &bearing_damping[b]}) {
      if (a->rows() != 3 || a->cols() != n)
        throw std::invalid_argument("HarmonicModel.bearing_stiffness/damping must be 3 x n");
    }
  }
  if (body_angles.cols() != n && body_angles.rows() != 0)
    throw std::invalid_argument("HarmonicModel.body_angles must have n columns");
}

HarmonicSolver::HarmonicSolver(const HarmonicModel& model) : model_(model) {
  model.CheckSizes();
  stiffness_ = model.K;
  still_damping_ = model.C;
  for (size_t i = 0; i < model.mesh_vectors.size(); ++i) {
    const Eigen::VectorXd& v = model.mesh_vectors[i];
    stiffness_.noalias() += model.mesh_stiffness[i] * v * v.transpose();
    still_damping_.noalias() += model.mesh_damping[i] * v * v.transpose();
  }
  const long n = model.M.rows();
  z_.resize(n, n);
  rhs_.resize(n);
  q_.resize(n);
  SetSpeed(0.0);
}

void HarmonicSolver::SetSpeed(double input_speed) {
  damping_ = still_damping_ + input_speed * model_.G;
}

void HarmonicSolver::Solve(double w, const HarmonicInput& input, HarmonicResponse& out) {
  const std::complex<double> iw(0.0, w);
  z_.real() = stiffness_ - w * w * model_.M;
  z_.imag() = w * damping_;
  lu_.compute(z_);
  rhs_.setZero();
  if (input.body_torque.size() > static_cast<size_t>(model_.body_angles.rows()))
    throw std::invalid_argument("HarmonicInput.body_torque: more bodies than body_angles rows");
  for (size_t b = 0; b < input.body_torque.size(); ++b) {
    if (input.body_torque[b] != 0.0)
      rhs_ += input.body_torque[b] * model_.body_angles.row(static_cast<Eigen::Index>(b))
                                         .transpose()
                                         .cast<std::complex<double>>();
  }
  const size_t meshes = model_.mesh_vectors.size();
  for (size_t i = 0; i < input.mesh.size() && i < meshes; ++i) {
    if (input.mesh[i] != 0.0)
      rhs_ += (model_.mesh_stiffness[i] * input.mesh[i]) * model_.mesh_vectors[i];
  }
  q_ = lu_.solve(rhs_);
  out.te.resize(meshes);
  out.mesh_force.resize(meshes);
  for (size_t i = 0; i < meshes; ++i) {
    const std::complex<double> delta = model_.mesh_vectors[i].dot(q_);
    const std::complex<double> e = i < input.mesh.size() ? input.mesh[i] : 0.0;
    out.te[i] = model_.te_vectors[i].dot(q_);
    out.mesh_force[i] = (model_.mesh_stiffness[i] + iw * model_.mesh_damping[i]) * delta -
                        model_.mesh_stiffness[i] * e;
  }
  out.bearing_force.resize(model_.bearing_stiffness.size());
  for (size_t b = 0; b < model_.bearing_stiffness.size(); ++b) {
    out.bearing_force[b] = model_.bearing_stiffness[b] * q_ + iw * (model_.bearing_damping[b] * q_);
  }
  out.body_speed.resize(static_cast<size_t>(model_.body_angles.rows()));
  for (long r = 0; r < model_.body_angles.rows(); ++r)
    out.body_speed[static_cast<size_t>(r)] = iw * model_.body_angles.row(r).dot(q_);
}

}  // namespace gearnvh
