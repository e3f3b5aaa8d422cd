#include "gearnvh/model/timoshenko_beam.h"

#include <numbers>

namespace gearnvh {

BeamSection BeamSection::Tube(double outer_diameter, double inner_diameter, double nu) {
  const double ro = 0.5 * outer_diameter, ri = 0.5 * inner_diameter;
  const double pi = std::numbers::pi;
  BeamSection s;
  s.area = pi * (ro * ro - ri * ri);
  s.second_moment = pi * (ro * ro * ro * ro - ri * ri * ri * ri) / 4.0;
  s.polar_moment = 2.0 * s.second_moment;
  const double m = ri / ro, m2 = (1.0 + m * m) * (1.0 + m * m);
  s.shear_coefficient =
      6.0 * (1.0 + nu) * m2 / ((7.0 + 6.0 * nu) * m2 + (20.0 + 12.0 * nu) * m * m);
  return s;
}

BeamElementMatrices TimoshenkoBeamElement(const BeamSection& sec, const Material& mat, double l,
                                          bool shear) {
  using Mat4 = Eigen::Matrix4d;
  const double E = mat.youngs_modulus, rho = mat.density;
  const double G = E / (2.0 * (1.0 + mat.poisson_ratio));
  const double A = sec.area, I = sec.second_moment, J = sec.polar_moment;
  const double phi = shear ? 12.0 * E * I / (sec.shear_coefficient * G * A * l * l) : 0.0;
  const double l2 = l * l;

  Mat4 kb;
  kb << 12, 6 * l, -12, 6 * l,                        //
      6 * l, (4 + phi) * l2, -6 * l, (2 - phi) * l2,  //
      -12, -6 * l, 12, -6 * l,                        //
      6 * l, (2 - phi) * l2, -6 * l, (4 + phi) * l2;
  kb *= E * I / ((1 + phi) * l2 * l);

  const double p2 = phi * phi;
  const double a = 13.0 / 35 + 7 * phi / 10 + p2 / 3;
  const double b = (11.0 / 210 + 11 * phi / 120 + p2 / 24) * l;
  const double c = 9.0 / 70 + 3 * phi / 10 + p2 / 6;
  const double d = (13.0 / 420 + 3 * phi / 40 + p2 / 24) * l;
  const double e = (1.0 / 105 + phi / 60 + p2 / 120) * l2;
  const double f = (1.0 / 140 + phi / 60 + p2 / 120) * l2;
  Mat4 mt;
  mt << a, b, c, -d,  //
      b, e, d, -f,    //
      c, d, a, -b,    //
      -d, -f, -b, e;
  mt *= rho * A * l / ((1 + phi) * (1 + phi));

  const double g = 6.0 / 5;
  const double h = (1.0 / 10 - phi / 2) * l;
  const double i2 = (2.0 / 15 + phi / 6 + p2 / 3) * l2;
  const double j2 = (1.0 / 30 + phi / 6 - p2 / 6) * l2;
  Mat4 mr;
  mr << g, h, -g, h,   //
      h, i2, -h, -j2,  //
      -g, -h, g, -h,   //
      h, -j2, -h, i2;
  mr *= rho * I / ((1 + phi) * (1 + phi) * l);

  const Mat4 D = Eigen::Vector4d(1, -1, 1, -1).asDiagonal();
  const int xz[4] = {0, 4, 6, 10};  // u_x1, th_y1, u_x2, th_y2
  const int yz[4] = {1, 3, 7, 9};   // u_y1, th_x1, u_y2, th_x2

  BeamElementMatrices out;
  out.stiffness.setZero();
  out.mass.setZero();
  out.gyroscopic.setZero();
  const Mat4 kb_yz = D * kb * D, m_xz = mt + mr, m_yz = D * (mt + mr) * D;
  const Mat4 g_yz_xz = -(J / I) * D * mr, g_xz_yz = (J / I) * mr * D;
  for (int r = 0; r < 4; ++r) {
    for (int s = 0; s < 4; ++s) {
      out.stiffness(xz[r], xz[s]) = kb(r, s);
      out.stiffness(yz[r], yz[s]) = kb_yz(r, s);
      out.mass(xz[r], xz[s]) = m_xz(r, s);
      out.mass(yz[r], yz[s]) = m_yz(r, s);
      out.gyroscopic(yz[r], xz[s]) = g_yz_xz(r, s);
      out.gyroscopic(xz[r], yz[s]) = g_xz_yz(r, s);
    }
  }
  // Axial (u_z) and torsion (th_z).
  const double ka = E * A / l, kt = G * J / l;
  const double ma = rho * A * l / 6.0, mtor = rho * J * l / 6.0;
  for (auto [dof, k, m] : {std::tuple{2, ka, ma}, std::tuple{5, kt, mtor}}) {
    out.stiffness(dof, dof) = out.stiffness(dof + 6, dof + 6) = k;
    out.stiffness(dof, dof + 6) = out.stiffness(dof + 6, dof) = -k;
    out.mass(dof, dof) = out.mass(dof + 6, dof + 6) = 2 * m;
    out.mass(dof, dof + 6) = out.mass(dof + 6, dof) = m;
  }
  return out;
}

}  // namespace gearnvh
