// The mesh misalignment the shafts' deflection under the static load gives (docs/design.md §2.5).
//
// Statics of the full FE model with every mesh engaged at its mean stiffness, its free rotations
// held: (K + s P P^T) x = f, P the orthonormal free rotations (K P = 0), exact for a balanced f
// (P^T f = 0) whatever s > 0. A gear node's displacement (u, th) moves the face point at axial
// offset z by u + th x z e_z = u + z (th_y, -th_x, 0), so mesh approach delta = v^T x changes
// across the face at d delta / dz = sum over the two gears of v_ux th_y - v_uy th_x, and the
// separation grows where delta falls: f_sh = -b d delta / dz over the common face b (the sign of
// MeshSpec::misalignment). The load is taken at the face centre (the mesh vector's point).
#pragma once

#include <Eigen/Dense>
#include <Eigen/Sparse>

namespace gearnvh {

Eigen::VectorXd StaticDeflection(const Eigen::SparseMatrix<double>& K, const Eigen::VectorXd& f,
                                 const Eigen::MatrixXd& free_rotations);

// f_sh of the mesh with vector v between the gear nodes node_a and node_b, m.
double TiltMisalignment(const Eigen::VectorXd& v, const Eigen::VectorXd& x, int node_a, int node_b,
                        double face_width);

}  // namespace gearnvh
