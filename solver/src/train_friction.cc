// Tooth friction on gear trains (train_tables.h): the meshes' force directions and the mean
// friction loss the input supplies.
#include <vector>

#include "gearnvh/solver/train_tables.h"

namespace gearnvh {
namespace {

// w_ij of one flank's segment: sigma t + a1 arm_a + a2 arm_b.
Eigen::VectorXd FrictionVector(const FlankSegment& s, const Eigen::VectorXd& slide,
                               const FrictionBasis& basis) {
  return s.friction_sigma * slide + s.friction_arm_pinion * basis.arm_a +
         s.friction_arm_wheel * basis.arm_b;
}

}  // namespace

void SetFrictionForces(TrainMeshTable& mt, const FrictionBasis& basis) {
  mt.force_drive.clear();
  mt.force_back.clear();
  if (!(mt.friction > 0.0)) return;
  for (int j = 0; j < mt.segments(); ++j) {
    const size_t s = static_cast<size_t>(j);
    mt.force_drive.push_back(
        mt.v + mt.friction * FrictionVector(mt.drive_flank[s], basis.slide_drive, basis));
    mt.force_back.push_back(
        mt.v_back - mt.friction * FrictionVector(mt.back_flank[s], basis.slide_back, basis));
  }
}

double FrictionLossTorque(const TrainTables& t, const std::vector<bool>& back_loaded, int input) {
  // In static contact the flank's normal force is F (drive: k g = F; back: k g = -F), its torque
  // on the free rotation -F r^T u+ = -mu F r^T w+ or +F r^T u- = -mu F r^T w-: a brake of
  // mu F <r^T w> either way, balanced by dT r_in on the input body.
  double loss = 0.0;
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    const TrainMeshTable& mt = t.meshes[i];
    if (!mt.has_friction()) continue;
    const bool drive = !back_loaded[i];
    double mean = 0.0;  // mu <r^T w>, from mu w = +-(u - v)
    for (int j = 0; j < mt.segments(); ++j) {
      const size_t s = static_cast<size_t>(j);
      const double share = (mt.boundary[s + 1] - mt.boundary[s]) / mt.period;
      const Eigen::VectorXd w = drive ? mt.force_drive[s] - mt.v : mt.v_back - mt.force_back[s];
      mean += share * t.rigid_rotation.dot(w);
    }
    const double wheel_base = -mt.v[mt.body_b];  // r_b,b (tier 1: v = r_a e_a - r_b e_b)
    loss += mt.transmitted_torque / wheel_base * mean;
  }
  return loss / t.rigid_rotation[input];
}

}  // namespace gearnvh
