// TrainStructure: the structural model of a whole gear train (schema gearnvh/2,
// docs/gear-trains.md) — every shaft, gear body and mesh vector in one sparse M, C, K, G — built by
// AssembleTrainStructure() from the spec and its GearTrain (the mesh-level models).
//
// Parts (6 DOF per node [u_x, u_y, u_z, th_x, th_y, th_z], global axes, shafts along z):
// - an elastic shaft: Timoshenko FE with its bearings and lumped inertias (as the schema-1
//   ComponentModel; nodes at every gear's `at`);
// - a rigid shaft: one node at the shaft's z = 0 carrying its polar `inertia`; its bearings at
//   their `at` and its gears at theirs act through the rigid offset (structure_assembly.h); with no
//   bearings it sits on ComponentModelOptions' rigid supports (as a schema-1 gear without shafts);
// - a fixed gear: a rigid disk at its shaft's node (elastic: the node at `at`);
// - a loose gear: a node of its own, coupled to its shaft at `at` by its bearing (radial, axial and
//   tilting springs of TrainStructureOptions) and free to rotate about the axis;
// - a coupling: a torsional spring-damper between its two shafts' body nodes (th_z only).
// Gyroscopic matrices are per unit input speed (each body's spin is its signed speed ratio).
// Layout: mesh i's line of centres points from its first gear to its second at the angle
// TrainMesh::center_line_angle about +z from +x (default 0: an unfolded planar layout); its vectors
// are built along +x and turned by that angle (translations and tilts of both gears).
// Mesh i: its first gear turns with sense s_a = sign(speed) about z; its vectors are those of the
// schema-1 pair (component_model.h) mirrored (y -> -y) when s_a = -1, so the torsional part is
//   delta_i = s_a (r_b,a th_z,a + r_b,b th_z,b) = r_b,a theta_a - r_b,b theta_b  (running angles),
// plus the lateral terms and, for a helical pair, the axial and tilting terms. The rotation arms of
// the friction vectors act on s_a th_z.
// Free rotations: body j's rigid rotation R_j (th_z = 1 on every node of the body) leaves the
// structure unstrained; a combination sum c_j R_j is free when every engaged mesh sees no approach,
// B c = 0 with B_ij = v_i^T R_j, and no coupling twists (c_a = c_b: a row r, -r, r the largest
// base radius, so that every row is in metres). They are found as the null space of B (SVD,
// singular values below 1e-9 of the largest are zero; B's entries are base radii, so the test is
// scale-free).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_train.h"

namespace gearnvh {

struct TrainStructureOptions {
  ComponentModelOptions structure;  // rigid supports and default element count (schema 1's)
  // The bearing of a loose gear on its shaft (needle bearing, ~30 mm bore).
  double loose_radial_stiffness = 2e8;  // N/m, > 0
  double loose_axial_stiffness = 5e7;   // N/m, > 0 (the axial stop)
  double loose_tilt_stiffness = 2e4;    // N m/rad, > 0
  double loose_damping = 200.0;         // N s/m, >= 0
  void Validate() const;
};

struct TrainMeshVectors {
  Eigen::VectorXd v_drive, v_back;
  Eigen::VectorXd friction_drive, friction_back;  // translation parts [t; -t]
  double sense = 1.0;                             // s_a
};

// A bearing between a shaft and the housing: one of the shaft's own, or the support of a rigid
// shaft that lists none (index -1, TrainStructureOptions::structure's rigid supports). Its point
// lies at `offset` along the axis from `node` (a rigid shaft's one node; 0 on an elastic shaft,
// whose bearing sits at its nearest node) and moves with u + th x (offset e_z).
struct StructureBearing {
  int shaft = 0;        // index in TrainSpec::shafts
  int index = -1;       // in the shaft's bearings; -1: the default support
  double at = 0.0;      // m along the shaft, as written
  int node = 0;
  double offset = 0.0;  // m
  double radial_stiffness = 0.0, axial_stiffness = 0.0, damping = 0.0;  // N/m, N/m, N s/m
  double tilt_stiffness = 0.0;                                          // N m/rad
};

struct TrainStructure {
  std::vector<FeNode>
      nodes;  // FeNode::shaft = index in TrainSpec::shafts (a loose gear: its shaft)
  std::vector<int> node_body;  // body of each node
  int dofs = 0;
  Eigen::SparseMatrix<double> M, C, K, G;
  std::vector<int> gear_node;            // per gear (TrainSpec::gears order)
  std::vector<TrainMeshVectors> meshes;  // per mesh (file order)
  std::vector<double> mean_stiffness;    // k_mean per mesh, N/m
  // c = 2 zeta sqrt(k_mean m_e) per mesh (TrainMeshModel::Damping), N s/m.
  std::vector<double> mesh_damping;
  // Per body, the node whose th_z is its angle: its first gear's (a fixed shaft without fixed
  // gears: its first node).
  std::vector<int> body_node;
  std::vector<int> elastic_shafts;  // indices in TrainSpec::shafts with FE
  // Per coupling (GearTrain::couplings) its two bodies; its spring (the first stage's) and damper
  // are in K and C between their body nodes' th_z.
  std::vector<std::pair<int, int>> coupled_bodies;
  // Per coupling its twist th_z,a - th_z,b as a row on the DOFs, and what its stages add to its
  // stiffness at the static twist (TrainCouplingModel::StaticStiffness - stiffness; 0 for a
  // linear coupling or one whose static twist stays in its first stage), N m/rad.
  std::vector<Eigen::VectorXd> coupling_twist;
  std::vector<double> coupling_static_increment;
  std::vector<StructureBearing> bearings;  // shafts in file order, each shaft's in its order
  // Rigid rotation of every body (dofs x bodies) and the free rotations with every mesh engaged
  // (dofs x count, orthonormal combinations of the body rotations).
  Eigen::MatrixXd body_rotations, free_rotations;
  Eigen::VectorXd static_force;  // input torque and loads at each body's node, N m

  static int Dof(int node, NodeDof d) { return 6 * node + static_cast<int>(d); }
  // The stiffness linearised with every mesh in drive contact at its mean stiffness and every
  // coupling in the stage of its static twist.
  Eigen::SparseMatrix<double> EngagedStiffness() const;
};

TrainStructure AssembleTrainStructure(const TrainSpec& spec, const GearTrain& train,
                                      const TrainStructureOptions& options = {});

// The free rotations (dofs x count) when only the meshes with engaged[i] are in contact (a loose
// gear in flight adds its own): the null space of B restricted to those meshes (see the header).
Eigen::MatrixXd FreeRotations(const TrainStructure& structure, const std::vector<bool>& engaged);

}  // namespace gearnvh
