// The inputs of a gear train (train_tables.h): the engine orders' exosystem and the meshes'
// manufacturing error inputs.
#include <cmath>

#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

void AssignErrorInputs(TrainTables& t) {
  t.error_inputs = 0;
  for (TrainMeshTable& mt : t.meshes) mt.error_input = mt.errors.active() ? t.error_inputs++ : -1;
  t.m = 2 * t.n + 1 + t.excitation_states() + t.error_inputs;
}

int TrainTables::ErrorSlot(int mesh) const {
  const int k = meshes[static_cast<size_t>(mesh)].error_input;
  return k < 0 ? -1 : 2 * n + 1 + excitation_states() + k;
}

double TrainTables::ErrorInput(int mesh, const Eigen::Ref<const Eigen::VectorXd>& z) const {
  const int slot = ErrorSlot(mesh);
  return slot < 0 ? 0.0 : z[slot];
}

double TrainTables::Wall(int mesh, int segment, bool drive,
                         const Eigen::Ref<const Eigen::VectorXd>& z) const {
  return Wall(mesh, segment, drive) * z[constant_slot()] + ErrorInput(mesh, z);
}

void TrainTables::SetInputs(const std::vector<long>& cycles, const std::vector<int>& segments,
                            double start, double h, Eigen::Ref<Eigen::VectorXd> z) const {
  SetExcitation(start, z);
  for (size_t i = 0; i < meshes.size(); ++i) {
    const TrainMeshTable& mt = meshes[i];
    if (mt.error_input < 0) continue;
    // The mesh's own cycle count and segment select the pitch errors' teeth; runout is averaged
    // over the grid segment itself (a part of the mesh segment on the union grid).
    z[ErrorSlot(static_cast<int>(i))] = mt.errors.SegmentMean(cycles[i], segments[i], start, h);
  }
}

void TrainTables::SetExcitation(double t, Eigen::Ref<Eigen::VectorXd> z) const {
  SetOrderStates(excitation, input_speed, t, ExcitationSlot(0), z);
}

void TrainTables::AddExcitationColumns(Eigen::Ref<Eigen::MatrixXd> A) const {
  AddOrderColumns(excitation, input_speed, n, ExcitationSlot(0),
                  excitation_directions.array().colwise() / inertia.array(), A);
}

void TrainTables::AddExcitationAcceleration(double t,
                                            Eigen::Ref<Eigen::VectorXd> acceleration) const {
  for (size_t k = 0; k < excitation.size(); ++k) {
    const ExcitationOrder& e = excitation[k];
    acceleration += (e.amplitude * std::sin(e.order * input_speed * t + e.phase)) *
                    excitation_directions.col(static_cast<Eigen::Index>(k)).cwiseQuotient(inertia);
  }
}

double TrainTables::HighestExcitationFrequency() const {
  return HighestOrderFrequency(excitation, input_speed);
}

void TrainTables::AddErrorColumns(const std::vector<int>& segments,
                                  const std::vector<ContactState>& states,
                                  Eigen::Ref<Eigen::MatrixXd> A) const {
  for (size_t i = 0; i < meshes.size(); ++i) {
    const TrainMeshTable& mt = meshes[i];
    if (mt.error_input < 0 || states[i] == ContactState::kFree) continue;
    // The error moves the wall: force -u_ij (k (v^T x - e - u -+ b) + ...), so u enters as
    // +k u_ij (u_ij = v without friction).
    const bool drive = states[i] == ContactState::kDrive;
    const size_t j = static_cast<size_t>(segments[i]);
    const double k = drive ? mt.k_drive[j] : mt.k_back[j];
    const Eigen::VectorXd& v = mt.ForceVector(segments[i], drive);
    const int slot = ErrorSlot(static_cast<int>(i));
    for (int r = 0; r < n; ++r) A(n + r, slot) += k * v[r] / inertia[r];
  }
}

}  // namespace gearnvh
