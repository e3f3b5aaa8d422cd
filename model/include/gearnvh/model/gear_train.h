// GearTrain: the component model of a gear train (schema gearnvh/2, docs/gear-trains.md): its
// bodies with their nominal speeds and polar inertias, and per mesh the mesh-level model (geometry,
// deformation-compatible stiffness over the cycle, load sharing, LSTE) at the torque that mesh
// transmits. A schema-1 gearbox is the train TrainOf(spec).
//
// Static torque flow: every load resists its body's rotation; the input shaft is driven by the
// torque that balances them all (power balance, T_in |w_in| = sum T_j |w_j|). On the spanning tree
// of the meshes and couplings each carries the power of the bodies beyond it; a mesh that closes a
// kinematic loop makes the split statically indeterminate and is analysed unloaded (warned).
//
// Tier 1 of a train (torsional): one rotation per body, each in its own direction of nominal
// rotation; mesh i couples its bodies through delta_i = r_b,a th_a - r_b,b th_b and coupling j its
// shafts through th_a - th_b (they turn alike), so
//   M = diag(J_body),  K = sum_i k_mean,i v_i v_i^T + sum_j k_j w_j w_j^T,
//   v_i = r_b,a e_a - r_b,b e_b,  w_j = e_a - e_b.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/mesh_pair.h"
#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/model/mesh_stiffness.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh {

struct TrainMeshModel {
  std::string name;  // "g1-g2"
  int gear_a = 0, gear_b = 0;
  int body_a = 0, body_b = 0;
  GearboxSpec gearbox;  // the mesh as the schema-1 gearbox of its two gears
  MeshPair pair;
  PairGeometry geometry;  // at the nominal speed of gear a
  MeshCycle cycle;
  MeshStiffnessSummary stiffness;
  // The cycle's segments at analysis.segments_per_cycle: built here so that every command (check as
  // well as simulate) applies SegmentMeshCycle's rule on the mandatory breaks.
  MeshSegmentation segmentation;
  double transmitted_torque = 0.0;  // N m on gear b (>= 0)
  // m_e, kg, by the mesh's MeshEffectiveMass rule, and the mesh damping c = 2 zeta sqrt(k_mean
  // m_e), N s/m, zeta = gearbox.mesh.damping_ratio.
  double effective_mass = 0.0;
  double Damping() const;
  bool back_flank_loaded = false;   // the second gear drives (power flows from b to a)
  bool in_loop = false;             // closes a kinematic loop: analysed unloaded
};

// A coupling between two shaft bodies (TrainCoupling): its torque k (th_a - th_b) + c (th_a' -
// th_b') on b, the shafts' angles in their common direction of rotation.
struct TrainCouplingModel {
  std::string name;
  int body_a = 0, body_b = 0;
  double stiffness = 0.0;                  // N m/rad (the first stage's)
  std::vector<TrainCouplingStage> stages;  // after the first (TrainCoupling::stages)
  double damping = 0.0;                    // N m s/rad
  double mean_torque = 0.0;                // N m, signed as TrainTorqueFlow::coupling_torque
  CouplingSprings springs() const { return {stiffness, stages}; }
  double MeanTwist() const { return springs().StaticTwist(mean_torque); }  // rad
  // The stiffness at the mean twist (N m/rad): the stage the static point lies in, which the
  // natural frequencies of `check` and the Campbell diagram use.
  double StaticStiffness() const { return springs().TangentStiffness(MeanTwist()); }
};

struct GearTrain {
  TrainTopology topology;
  std::vector<double> body_inertia;  // polar, kg m^2, per body
  std::vector<TrainMeshModel> meshes;
  std::vector<TrainCouplingModel> couplings;
  double input_torque = 0.0;  // N m driving the input shaft (balances every load)
  std::vector<std::string> warnings;
};

GearTrain BuildGearTrain(const TrainSpec& spec, const MeshStiffnessOptions& options = {});

// The polar inertia of every body (kg m^2): a shaft's own (rigid `inertia` or its FE's) with its
// fixed gears' disks; a loose gear's disk.
std::vector<double> BodyInertias(const TrainSpec& spec, const TrainTopology& topology);

// The train of `at`, a spec that differs from the one `train` was built from only in
// operating.speed and the amplitudes of operating.excitation, without building its meshes again: a
// mesh's stiffness over the cycle, its segmentation and the static torque flow depend on the
// geometry and the loads, not on the speed (the flow balances power, T_in |w_in| = sum T_j |w_j|,
// in ratios of speeds), and a GearTrain holds no excitation amplitude (the tables do). The
// topology's body speeds and each mesh's pair and geometry (mesh frequency) are those of `at`.
// Equal, field by field, to BuildGearTrain(at) (tests/model/gear_train_test.cc); a speed sweep
// builds each speed's train this way (the meshes were ~90 % of a speed's cost). With a viscous
// drag the loads depend on the speed, and this is BuildGearTrain(at).
GearTrain GearTrainAtSpeed(GearTrain train, const TrainSpec& at);

// Tier 1 of the train: torsional natural frequencies at the mean mesh stiffnesses and the mode
// shapes (bodies x modes, M-normalised). The free rotations are found as the null space of the
// meshes' and couplings' vectors (one for a connected train: th_j proportional to |w_j|) and
// removed.
struct TrainTorsionalModes {
  int free_rotations = 0;
  std::vector<double> frequencies_hz;
  Eigen::MatrixXd shapes;
  Eigen::MatrixXd M, K;  // the tier-1 matrices
};
TrainTorsionalModes TorsionalModes(const GearTrain& train);

}  // namespace gearnvh
