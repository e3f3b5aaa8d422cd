#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "whine_parts.h"

namespace gearnvh {

double WhineMode::MeshEnergy() const {
  double sum = 0.0;
  for (double e : mesh_energy) sum += e;
  return sum;
}

namespace whine {

std::vector<WhineMode> Modes(const HarmonicModel& model, const TrainStructure& structure,
                             const TrainReducedModel& reduced, double limit_hz) {
  Eigen::MatrixXd k = model.K;
  for (size_t i = 0; i < model.mesh_vectors.size(); ++i)
    k += model.mesh_stiffness[i] * model.mesh_vectors[i] * model.mesh_vectors[i].transpose();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> eig(
      0.5 * (k + k.transpose()), 0.5 * (model.M + model.M.transpose()));
  std::vector<WhineMode> modes;
  if (eig.info() != Eigen::Success) return modes;
  const double largest = std::max(eig.eigenvalues().cwiseAbs().maxCoeff(), 1e-300);
  for (long j = 0; j < eig.eigenvalues().size(); ++j) {
    const double lambda = eig.eigenvalues()[j];
    if (lambda <= 1e-12 * largest) continue;  // the free rotation
    const double f = std::sqrt(lambda) / (2.0 * std::numbers::pi);
    if (f > limit_hz) break;
    const Eigen::VectorXd phi = eig.eigenvectors().col(j);
    const double total = phi.dot(k * phi);
    WhineMode m;
    m.frequency_hz = f;
    for (size_t i = 0; i < model.mesh_vectors.size(); ++i) {
      const double d = model.mesh_vectors[i].dot(phi);
      m.mesh_energy.push_back(model.mesh_stiffness[i] * d * d / total);
    }
    for (size_t b = 0; b < model.bearing_stiffness.size(); ++b) {
      const StructureBearing& sb = structure.bearings[b];
      const double springs[3] = {sb.radial_stiffness, sb.radial_stiffness, sb.axial_stiffness};
      double e = 0.0;
      for (int d = 0; d < 3; ++d) {
        // Row d of the bearing's stiffness rows is k_d times its point's motion.
        const double force = model.bearing_stiffness[b].row(d).dot(phi);
        if (springs[d] > 0.0) e += force * force / springs[d];
      }
      // Its tilt springs on the node's rotations about x and y (an offset does not turn them).
      for (NodeDof d : {kThx, kThy}) {
        const double tilt = reduced.recovery.row(TrainStructure::Dof(sb.node, d)).dot(phi);
        e += sb.tilt_stiffness * tilt * tilt;
      }
      m.bearing_energy.push_back(e / total);
    }
    modes.push_back(std::move(m));
  }
  return modes;
}

std::vector<WhineCriticalSpeed> CriticalSpeeds(const WhineResult& r) {
  std::vector<WhineCriticalSpeed> out;
  const double lo = r.speed_rad_s.front(), hi = r.speed_rad_s.back();
  for (size_t m = 0; m < r.modes.size(); ++m) {
    for (size_t l = 0; l < r.lines.size(); ++l) {
      const double speed = 2.0 * std::numbers::pi * r.modes[m].frequency_hz / r.lines[l].order;
      if (speed >= lo && speed <= hi) out.push_back({speed, l, m});
    }
  }
  std::stable_sort(out.begin(), out.end(), [&r](const auto& a, const auto& b) {
    const double ea = r.modes[a.mode].MeshEnergy(), eb = r.modes[b.mode].MeshEnergy();
    return ea != eb ? ea > eb : a.speed_rad_s < b.speed_rad_s;
  });
  return out;
}

}  // namespace whine
}  // namespace gearnvh
