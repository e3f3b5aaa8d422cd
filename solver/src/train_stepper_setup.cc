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

namespace {

// The static stiffness rows of the contact combination `states` (K x = f with each contact's
// spring at its segment-0 wall) and the centring row r~ x = 0 below them.
void StaticSystem(const TrainTables& t, const std::vector<ContactState>& states, Eigen::MatrixXd& B,
                  Eigen::VectorXd& rhs) {
  const int n = t.n;
  B = Eigen::MatrixXd::Zero(n + 1, n);
  if (t.structural_stiffness.size() > 0) B.topRows(n) = t.structural_stiffness;
  rhs = Eigen::VectorXd::Zero(n + 1);
  rhs.head(n) = t.force;
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    const TrainMeshTable& mt = t.meshes[i];
    if (states[i] == ContactState::kFree) continue;
    const bool drive = states[i] == ContactState::kDrive;
    const double k = drive ? mt.k_drive[0] : mt.k_back[0];
    const Eigen::VectorXd& u = mt.ForceVector(0, drive);  // v without friction
    B.topRows(n) += k * u * mt.Vector(drive).transpose();
    rhs.head(n) += k * t.Wall(static_cast<int>(i), 0, drive) * u;
  }
  // K x = f is singular along the free rotation (and more so with a free loose gear; with
  // friction also inconsistent along it, the loss balanced only in the cycle mean): the
  // least-squares solution with r~ x = 0 is the centred one.
  const double scale = std::max(B.topRows(n).norm(), 1.0) / t.recenter_row.norm();
  B.row(n) = scale * t.recenter_row;
}

// The state mesh i takes next, given the static solution z of its current contact state: a
// contact stays while its flank is pressed beyond the gap's rounding floor (GapTolerance); a drive
// contact pulled beyond it tries the back flank; a contact that carries no force (a mesh of a
// train without load sits exactly on its wall, where rounding alone would pick a side) is free.
ContactState NextStaticState(const TrainTables& t, size_t i, ContactState state,
                             const Eigen::VectorXd& z) {
  const int mesh = static_cast<int>(i);
  // A coupling's stage (it starts at its closed-form state: the torque flow's twist, without the
  // friction loss the input also supplies) follows the solved twist: engaged on the side it
  // passes, free between (its walls lie 2 a_s apart, so "drive pulled, try back" would not apply).
  if (!t.meshes[i].gear_mesh()) {
    if (t.GapValue(mesh, 0, true, z) > t.GapTolerance(mesh, 0, true, z))
      return ContactState::kDrive;
    if (t.GapValue(mesh, 0, false, z) < -t.GapTolerance(mesh, 0, false, z))
      return ContactState::kBack;
    return ContactState::kFree;
  }
  if (state == ContactState::kFree) return state;
  const bool drive = state == ContactState::kDrive;
  const double gap = t.GapValue(mesh, 0, drive, z);
  const double tolerance = t.GapTolerance(mesh, 0, drive, z);
  if (drive) {
    if (gap > tolerance) return state;
    return gap < -tolerance ? ContactState::kBack : ContactState::kFree;
  }
  return gap < -tolerance ? state : ContactState::kFree;
}

// Places every free mesh in the middle of its backlash where the contacts leave it free to move:
// along the null space N of the static system (which moves no contact's spring), the least-squares
// fit of each free mesh's mean gap row (v + v_back)/2 to the middle of its walls over the cycle.
// Nothing presses such a mesh, so any place is an equilibrium; the middle keeps the farthest from
// both walls as e_ij changes from segment to segment (the least-norm solution left the headset
// mesh of the manual transmission without load 2.6 um from its back wall).
void CentreFreeMeshes(const TrainTables& t, const std::vector<ContactState>& states,
                      const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>& cod,
                      Eigen::Ref<Eigen::VectorXd> x) {
  const int n = t.n;
  const long free_dims = n - cod.rank();
  std::vector<size_t> free;
  for (size_t i = 0; i < t.meshes.size(); ++i) {
    if (states[i] == ContactState::kFree) free.push_back(i);
  }
  if (free.empty() || free_dims <= 0) return;
  // B P = Q T Z with T's last n - rank columns zero: B's null space is P Z^T [0; I].
  const Eigen::MatrixXd null =
      cod.colsPermutation() * cod.matrixZ().bottomRows(free_dims).transpose();
  Eigen::MatrixXd rows(static_cast<long>(free.size()), n);
  Eigen::VectorXd misfit(static_cast<long>(free.size()));
  for (size_t k = 0; k < free.size(); ++k) {
    const TrainMeshTable& mt = t.meshes[free[k]];
    const auto [low, high] = std::minmax_element(mt.error.begin(), mt.error.end());
    rows.row(static_cast<long>(k)) = 0.5 * (mt.v + mt.v_back).transpose();
    misfit[static_cast<long>(k)] = 0.5 * (*low + *high) - rows.row(static_cast<long>(k)).dot(x);
  }
  const Eigen::MatrixXd fit = rows * null;
  x += null * fit.completeOrthogonalDecomposition().solve(misfit);
}

}  // namespace

std::pair<Eigen::VectorXd, std::vector<ContactState>> TrainStaticState(const TrainTables& t) {
  const int n = t.n;
  std::vector<ContactState> states = LoadedContactStates(t);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(t.m);
  z[t.constant_slot()] = 1.0;
  Eigen::MatrixXd B;
  Eigen::VectorXd rhs;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  // Each pass fixes the contacts whose static gap contradicts their state; a mesh changes at most
  // twice (drive -> back -> free), a coupling's stage settles with its twist. z always solves the
  // states returned.
  for (size_t pass = 0;; ++pass) {
    StaticSystem(t, states, B, rhs);
    cod.compute(B);
    z.head(n) = cod.solve(rhs);
    if (pass == 2 * t.meshes.size() + 1) break;
    bool changed = false;
    for (size_t i = 0; i < t.meshes.size(); ++i) {
      const ContactState next = NextStaticState(t, i, states[i], z);
      changed = changed || next != states[i];
      states[i] = next;
    }
    if (!changed) break;
  }
  CentreFreeMeshes(t, states, cod, z.head(n));
  return {z, states};
}

std::vector<ContactState> LoadedContactStates(const TrainTables& tables) {
  std::vector<ContactState> states(tables.meshes.size(), ContactState::kDrive);
  for (size_t i = static_cast<size_t>(tables.gear_meshes); i < tables.meshes.size(); ++i)
    states[i] = tables.meshes[i].static_state;
  return states;
}

}  // namespace gearnvh
