// Building blocks of the structural assembly shared by the single pair (component_model.cc) and
// the gear train (train_structure.cc): triplet assembly of bodies, supports and couplings (also at
// an axial offset from a rigid shaft's node), the Timoshenko FE of an elastic shaft, and the
// line-of-action vectors of a mesh. Internal to the model library.
//
// Offset attachment: a point at axial distance d from a node of a rigid body moves with
//   u_p = u + th x (d e_z) = [u_x + d th_y, u_y - d th_x, u_z],  th_p = th   (u_p = T(d) q_node),
// so a matrix A at the point adds T^T A T at the node and a vector f at the point adds T^T f.
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <vector>

#include "gearnvh/model/component_model.h"

namespace gearnvh::detail {

using Triplets = std::vector<Eigen::Triplet<double>>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// T(d) of the header.
Matrix6 OffsetTransform(double d);

struct Assembler {
  Triplets m, c, k, g;
  void Add(Triplets& t, int i, int j, double v) {
    if (v != 0.0) t.emplace_back(i, j, v);
  }
  // Rigid disk at a node; gyroscopics per unit input speed times `spin` (the body's speed ratio).
  void AddBody(int node, const GearBody& b, double spin);
  // Radial, axial and tilting springs (and radial/axial dampers) from a node to ground.
  void AddSupport(int node, double radial, double axial, double tilt, double damping);
  // The same at axial offset d from a rigid node.
  void AddBodyAt(int node, double d, const GearBody& b, double spin);
  void AddSupportAt(int node, double d, double radial, double axial, double tilt, double damping);
  // Springs between node `a` and the point at offset d from node `b` on every DOF but the
  // rotation about the axis (a loose gear on its bearing).
  void AddCoupling(int a, int b, double d, double radial, double axial, double tilt,
                   double damping);
  // Adds the 6x6 block A of the point at offset d from `node` to triplets t.
  void AddLocal(Triplets& t, int node, double d, const Matrix6& A);
};

// Node positions of an elastic shaft: key points (ends, segment joints, the given gear positions,
// bearings, inertias), then subdivided to the element length.
std::vector<double> ShaftNodePositions(const ShaftSpec& shaft, const std::vector<double>& gears,
                                       int default_elements_per_shaft);

// The node of `shaft` nearest to z.
int NearestNode(const std::vector<FeNode>& nodes, int shaft, double z);

// Appends an elastic shaft's nodes and Timoshenko elements (spin: gyroscopics per unit input
// speed); returns its first node.
int AddShaftElements(const ShaftSpec& shaft, const Material& material, int shaft_id,
                     const std::vector<double>& gears, double spin, int default_elements_per_shaft,
                     std::vector<FeNode>& nodes, Assembler& as);

// Adds an elastic shaft's bearings and lumped inertias at their nearest nodes.
void AddShaftSupports(const ShaftSpec& shaft, int shaft_id, double spin,
                      const std::vector<FeNode>& nodes, Assembler& as);

Eigen::SparseMatrix<double> ToSparse(int n, const Triplets& t);

// The line-of-action vectors of one mesh at its two gear points, as 12-vectors [gear a; gear b]
// (see component_model.h). `sense` = +1 when gear a turns about +z (the schema-1 pinion), -1 when
// it turns about -z: the mesh is then the mirror image (y -> -y) of the +1 case, so the lines of
// action are n = (sin a_w, sense cos a_w), n' = (sin a_w, -sense cos a_w), the torsional terms
// sense r_b, and the helical sign s = sense tan(beta_b) (-s for a left-hand gear a).
struct LocalMeshVectors {
  Eigen::Matrix<double, 12, 1> drive, back, friction_drive, friction_back;
};
LocalMeshVectors MeshLineOfAction(const PairGeometry& geometry, Hand hand_a, double sense);

// Adds the 6-vector part of a point vector (offset d from node) into a global vector.
void ScatterAt(const Vector6& local, int node, double d, Eigen::VectorXd& global);

}  // namespace gearnvh::detail
