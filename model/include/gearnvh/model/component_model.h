// ComponentModel: the assembled gearbox — mesh (stiffness over the cycle, segments) and structure
// (sparse M, C, K, G of shafts, bearings, gear bodies and driveline inertias) — built from a
// GearboxSpec by BuildComponentModel(). docs/design.md §2.
//
// Coordinates (global, SI): shafts along z; pinion centre at (0, 0), wheel centre at (a, 0); 6 DOF
// per node [u_x, u_y, u_z, th_x, th_y, th_z]. The pinion runs at +Omega1 about z, the wheel at
// -Omega1 r_b1 / r_b2 (so a positive wheel running angle is -th_z).
// Drive line of action n = (sin a_w, cos a_w), back line n' = (sin a_w, -cos a_w); t = z × n.
// Gap coordinates: delta = v_drive^T q (drive contact when delta > b), delta_b = v_back^T q (back
// contact when delta_b < -b), b = backlash / 2, with
//   v_drive = [ n at pinion u;  r_b1 at pinion th_z;  -n at wheel u;  r_b2 at wheel th_z ]
//   v_back  = [-n' at pinion u; r_b1 at pinion th_z;  n' at wheel u;  r_b2 at wheel th_z ]
// (torsional parts equal: delta = r_b1 th1 - r_b2 th2 in running angles, the classic TE).
// A helical pair's line of action is inclined by the base helix angle beta_b: with the stiffness
// k_t of the transverse approach, the approach is delta = v^T q with
//   v += s [u_z at pinion: 1; at wheel: -1; (th_x, th_y) at pinion: -r_b1 n; at wheel: -r_b2 n]
// (back flank: +r_b1 n', +r_b2 n' on the tilts), s = tan(beta_b) (-tan for a left-hand pinion):
// the relative axial displacement of the contact points (the gears' axial translations and the
// tilts acting through the contact points' arms rho x z, rho = -r_b1 t on the pinion's drive
// flank), so the mesh force carries its axial component F tan(beta_b) and the tilting moments.
// Tiers 1-2 keep no axial or tilt DOF and see the spur vector.
// Mesh force on q in contact: drive  -k (delta - b - e)(v_drive + mu w_drive),
//                             back   -k (delta_b + b - e)(v_back - mu w_back),
// friction vector w = sigma [t at pinion u; -t at wheel u] + a1 e_pinion_thz + a2 e_wheel_thz with
// the flank's own t and the segment's (sigma, a1, a2) from MeshSegment. Hence the mesh stiffness in
// contact is the rank-1 k (v ± mu w) v^T (non-symmetric with friction).
// Gyroscopic force: Omega1 G q̇ (G already carries the wheel shaft's spin ratio and sign).
// Static load: operating torque T on the wheel (+z, resisting), T r_b1/r_b2 on the pinion (+z).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <string>
#include <vector>

#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/manufacturing_errors.h"
#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/model/mesh_stiffness.h"

namespace gearnvh {

struct ComponentModelOptions {
  MeshStiffnessOptions mesh;
  // Supports of a gear without `shafts:` (rigid shaft on two bearings, lumped at the gear).
  double rigid_radial_stiffness = 5e8;  // N/m, > 0 (two bearings of 2.5e8 N/m)
  double rigid_axial_stiffness = 2e8;   // N/m, > 0
  double rigid_tilt_stiffness = 1e6;    // N m/rad, > 0 (bearing pair ~100 mm apart)
  double rigid_damping = 1e3;           // N s/m, >= 0
  // Default shaft element length: min(shaft length / this, smallest outer diameter); >= 2.
  int default_elements_per_shaft = 30;
  void Validate() const;
};

struct FeNode {
  int shaft = 0;   // 0: input (pinion), 1: output (wheel)
  double z = 0.0;  // m along the shaft from its left end
};

enum NodeDof { kUx = 0, kUy = 1, kUz = 2, kThx = 3, kThy = 4, kThz = 5 };

struct GearBody {
  double mass = 0.0;       // kg
  double polar = 0.0;      // I_p, kg m^2
  double diametral = 0.0;  // I_d, kg m^2
};

// A gear as a solid disk between its pitch and bore radii over its face width (the `inertia` and
// `mass` keys override).
GearBody DiskBody(const GearSpec& gear, const Material& material);

struct ComponentModel {
  // Mesh.
  PairGeometry geometry;
  MeshCycle cycle;
  MeshStiffnessSummary mesh_summary;
  MeshSegmentation segmentation;
  double half_backlash = 0.0;   // b, m
  double mesh_damping = 0.0;    // c = 2 zeta sqrt(k_mean m_e), N s/m
  double effective_mass = 0.0;  // m_e = J1 J2 / (J1 r_b2^2 + J2 r_b1^2), kg
  double friction_coefficient = 0.0;
  MeshErrorExcitation errors;  // runout and pitch errors as an input of the mesh

  // Structure.
  std::vector<FeNode> nodes;
  int dofs = 0;
  Eigen::SparseMatrix<double> M, C, K, G;
  Eigen::VectorXd v_drive, v_back;
  Eigen::VectorXd translation_friction_drive, translation_friction_back;  // [t; -t] parts
  int pinion_node = 0, wheel_node = 0;
  GearBody pinion_body, wheel_body;
  double pinion_side_inertia = 0.0;  // polar inertia rotating with the pinion, kg m^2
  double wheel_side_inertia = 0.0;
  Eigen::VectorXd static_force;  // N, N m
  double pinion_speed = 0.0;     // Omega1, rad/s
  bool flexible = false;         // built from `shafts:`
  std::vector<std::string> warnings;

  static int Dof(int node, NodeDof d) { return 6 * node + static_cast<int>(d); }
  int PinionDof(NodeDof d) const { return Dof(pinion_node, d); }
  int WheelDof(NodeDof d) const { return Dof(wheel_node, d); }
  // w for one flank and segment values (see the header comment).
  Eigen::VectorXd FrictionVector(Flank flank, double sigma, double arm_pinion,
                                 double arm_wheel) const;
};

ComponentModel BuildComponentModel(const GearboxSpec& spec,
                                   const ComponentModelOptions& options = {});

struct ModalSummary {
  std::vector<double> frequencies_hz;  // ascending, rigid-body modes excluded
  int rigid_body_modes = 0;
};

// Undamped natural frequencies of the full model linearised in drive contact at the mean mesh
// stiffness: (K + k_mean v v^T) phi = w^2 M phi (dense; for check and reporting). Rigid-body modes
// (the free rotation) by the criterion of modal_analysis.h with FullStrainMagnitude.
ModalSummary FullModelFrequencies(const ComponentModel& model, int count);

// |x|^T |K| |x| + k (|v|^T |x|)^2 of a full-model shape x at mesh stiffness k: the magnitude of
// the terms of its strain energy, the scale of the rigid-body test (modal_analysis.h) that the
// full model and every modal tier (shapes recovered) share.
double FullStrainMagnitude(const ComponentModel& model, double mesh_stiffness,
                           const Eigen::VectorXd& x);

}  // namespace gearnvh
