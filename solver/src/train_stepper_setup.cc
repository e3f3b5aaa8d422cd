// The train stepper's inputs (train_stepper.h): its options' rules, the union grid of the meshes'
// segment boundaries and the static state a run starts from.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_stepper.h"

namespace gearnvh {

void TrainStepperOptions::Validate() const {
  if (!(grazing_rate_tolerance >= 0.0)) {
    throw InputError("TrainStepperOptions.grazing_rate_tolerance", 0,
                     std::to_string(grazing_rate_tolerance), "must be >= 0");
  }
  if (max_events_per_segment < 1) {
    throw InputError("TrainStepperOptions.max_events_per_segment", 0,
                     std::to_string(max_events_per_segment), "must be >= 1");
  }
  if (max_cycle_map_segments < 1) {
    throw InputError("TrainStepperOptions.max_cycle_map_segments", 0,
                     std::to_string(max_cycle_map_segments), "must be >= 1");
  }
  if (min_jump_periods < 1) {
    throw InputError("TrainStepperOptions.min_jump_periods", 0, std::to_string(min_jump_periods),
                     "must be >= 1");
  }
  if (!(jump_margin_fraction >= 0.0 && jump_margin_fraction < 1.0)) {
    throw InputError("TrainStepperOptions.jump_margin_fraction", 0,
                     std::to_string(jump_margin_fraction), "must be in [0, 1)");
  }
  if (fusion_levels < 0 || fusion_levels > 16) {
    throw InputError("TrainStepperOptions.fusion_levels", 0, std::to_string(fusion_levels),
                     "must be in [0, 16]");
  }
  if (fusion_min_periods < 1) {
    throw InputError("TrainStepperOptions.fusion_min_periods", 0,
                     std::to_string(fusion_min_periods), "must be >= 1");
  }
  if (fusion_limit_bytes == 0) {
    throw InputError("TrainStepperOptions.fusion_limit_bytes", 0,
                     std::to_string(fusion_limit_bytes), "must be >= 1");
  }
  tables.Validate();
}

TrainGrid::TrainGrid(const TrainTables& tables)
    : t_(&tables), segment_(tables.meshes.size(), 0), cycle_(tables.meshes.size(), 0) {
  double shortest = std::numeric_limits<double>::infinity();
  for (const TrainMeshTable& mt : tables.meshes) shortest = std::min(shortest, mt.period);
  merge_ = 1e-12 * shortest;
  FindEnd();
}

void TrainGrid::FindEnd() {
  end_ = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < segment_.size(); ++i) {
    const TrainMeshTable& mt = t_->meshes[i];
    end_ = std::min(end_, static_cast<double>(cycle_[i]) * mt.period +
                              mt.boundary[static_cast<size_t>(segment_[i]) + 1]);
  }
}

void TrainGrid::Next() {
  // Every mesh whose boundary is this end (within rounding of the time) moves on.
  const double tolerance = merge_ + 4.0 * std::numeric_limits<double>::epsilon() * end_;
  for (size_t i = 0; i < segment_.size(); ++i) {
    const TrainMeshTable& mt = t_->meshes[i];
    const double boundary = static_cast<double>(cycle_[i]) * mt.period +
                            mt.boundary[static_cast<size_t>(segment_[i]) + 1];
    if (boundary <= end_ + tolerance) {
      if (++segment_[i] == mt.segments()) segment_[i] = 0, ++cycle_[i];
    }
  }
  start_ = end_;
  FindEnd();
}

std::pair<Eigen::VectorXd, std::vector<ContactState>> TrainStaticState(const TrainTables& t) {
  const int n = t.n;
  std::vector<ContactState> states(t.meshes.size(), ContactState::kDrive);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(t.m);
  z[t.constant_slot()] = 1.0;
  // Each pass fixes the meshes whose static gap contradicts their state; a mesh changes at most
  // twice (drive -> back -> free).
  for (size_t pass = 0; pass <= 2 * t.meshes.size(); ++pass) {
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(n + 1, n);
    if (t.structural_stiffness.size() > 0) B.topRows(n) = t.structural_stiffness;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + 1);
    rhs.head(n) = t.force;
    for (size_t i = 0; i < t.meshes.size(); ++i) {
      const TrainMeshTable& mt = t.meshes[i];
      if (states[i] == ContactState::kFree) continue;
      const bool drive = states[i] == ContactState::kDrive;
      const double k = drive ? mt.k_drive[0] : mt.k_back[0];
      const Eigen::VectorXd& v = mt.Vector(drive);
      const Eigen::VectorXd& u = mt.ForceVector(0, drive);  // v without friction
      B.topRows(n) += k * u * v.transpose();
      rhs.head(n) +=
          k * (drive ? mt.error[0] + mt.half_backlash : mt.error[0] - mt.half_backlash) * u;
    }
    // K x = f is singular along the free rotation (and more so with a free loose gear; with
    // friction also inconsistent along it, the loss balanced only in the cycle mean): the
    // least-squares solution with r~ x = 0 is the centred one.
    const double scale = std::max(B.topRows(n).norm(), 1.0) / t.recenter_row.norm();
    B.row(n) = scale * t.recenter_row;
    z.head(n) = B.completeOrthogonalDecomposition().solve(rhs);
    bool changed = false;
    for (size_t i = 0; i < t.meshes.size(); ++i) {
      const TrainMeshTable& mt = t.meshes[i];
      const double delta = mt.v.dot(z.head(n)) - mt.error[0];
      const double delta_back = mt.v_back.dot(z.head(n)) - mt.error[0];
      ContactState want = ContactState::kFree;
      if (delta > mt.half_backlash)
        want = ContactState::kDrive;
      else if (delta_back < -mt.half_backlash)
        want = ContactState::kBack;
      if (states[i] != ContactState::kFree && want != states[i]) {
        states[i] = states[i] == ContactState::kDrive ? ContactState::kBack : ContactState::kFree;
        changed = true;
      }
    }
    if (!changed) break;
  }
  return {z, states};
}

}  // namespace gearnvh
