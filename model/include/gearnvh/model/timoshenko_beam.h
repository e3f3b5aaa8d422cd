// Two-node Timoshenko beam element along z, 6 DOF per node: [u_x, u_y, u_z, th_x, th_y, th_z].
//
// Bending in the x–z plane uses (w = u_x, theta = th_y = dw/dz); in the y–z plane (w = u_y,
// theta = -th_x = dw/dz), i.e. the same 4x4 matrices with rotation signs flipped (D =
// diag(1,-1,1,-1)). With Phi = 12 E I / (kappa G A l^2) (Przemieniecki 1968; Nelson 1980):
//   K_b = E I / ((1 + Phi) l^3) [[12, 6l, -12, 6l], [6l, (4+Phi) l^2, -6l, (2-Phi) l^2], ...]
//   M_t = rho A l / (1+Phi)^2 [...],  M_r = rho I / ((1+Phi)^2 l) [...]   (consistent mass incl.
//   rotary inertia), torsion G J / l, rho J l / 6 [[2,1],[1,2]], axial E A / l, rho A l / 6
//   [[2,1],[1,2]].
// Gyroscopic matrix per unit spin about +z (force term Omega G q̇), from the disk equations
// I_d th_x'' + I_p Omega th_y' = M_x, I_d th_y'' - I_p Omega th_x' = M_y distributed along the
// element:
//   G[yz, xz] = -(J/I) D M_r,  G[xz, yz] = (J/I) M_r D   (skew-symmetric; J = 2 I for round
//   sections).
// Shear coefficient for a (hollow) circular section after Cowper (1966):
//   kappa = 6 (1+nu)(1+m^2)^2 / ((7+6nu)(1+m^2)^2 + (20+12nu) m^2),  m = r_i / r_o.
#pragma once

#include <Eigen/Dense>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct BeamSection {
  double area = 0.0;           // A, m^2
  double second_moment = 0.0;  // I (diametral), m^4
  double polar_moment = 0.0;   // J, m^4
  double shear_coefficient = 0.0;

  static BeamSection Tube(double outer_diameter, double inner_diameter, double poisson_ratio);
};

struct BeamElementMatrices {
  Eigen::Matrix<double, 12, 12> stiffness;
  Eigen::Matrix<double, 12, 12> mass;
  Eigen::Matrix<double, 12, 12> gyroscopic;  // per unit spin rate about +z
};

// `shear` false gives the Euler–Bernoulli limit (Phi = 0).
BeamElementMatrices TimoshenkoBeamElement(const BeamSection& section, const Material& material,
                                          double length, bool shear = true);

}  // namespace gearnvh
