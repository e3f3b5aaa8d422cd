// Single-tooth compliance of a spur gear by the potential energy method.
//
// The tooth is a variable-section cantilever on the gear body (Yang & Lin 1987; Tian 2004; Chen &
// Shao 2011). A unit normal force at a contact point with force angle alpha1 (between the force and
// the tooth's transverse direction) splits into F_b = cos(alpha1) (bending/shear) and
// F_a = sin(alpha1) (axial compression) applied at (x_P, h_P). With x along the tooth centre line
// from the gear centre and h(x) the half thickness:
//   1/k_b = ∫ [cos a1 (x_P - x) - sin a1 h_P]^2 / (E I_x) dx,   I_x = (2h)^3 L / 12
//   1/k_s = ∫ 1.2 cos^2 a1 / (G A_x) dx,                        A_x = 2 h L,  G = E / (2(1+nu))
//   1/k_a = ∫ sin^2 a1 / (E A_x) dx
// Involute part, parametrised by alpha in [alpha_start, alpha1] (alpha2 = half tooth angle on the
// base circle = pi/(2z) + inv(alpha0) + 2 x tan(alpha0)/z):
//   x = r_b [(alpha + alpha2) sin(alpha) + cos(alpha)],  h = r_b [(alpha + alpha2) cos(alpha) -
//   sin(alpha)], dx = r_b (alpha + alpha2) cos(alpha) d alpha.
// Where r_b > r_f the flank below the base circle is a straight line of constant half thickness
// r_b sin(alpha2) down to the root circle (Liang, Zuo & Pandey 2014); where r_f > r_b the involute
// is cut at the root circle. Gear-body (fillet-foundation) compliance of Sainsot, Velex & Duverger
// (2004):
//   1/k_f = cos^2 a1 / (E L) [L* (u_f/S_f)^2 + M* (u_f/S_f) + P* (1 + Q* tan^2 a1)],
//   u_f = x_P - r_f, S_f = 2 r_f theta_f, X*(h_f, theta_f) = A/theta_f^2 + B h_f^2 + C h_f/theta_f
//   + D/theta_f + E h_f + F, h_f = r_f / r_bore, theta_f = half tooth angle on the root circle.
// Units: compliances in m/N. The trochoidal fillet itself is not traced; see
// docs/mesh-stiffness.md.
#pragma once

#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/quadrature.h"

namespace gearnvh {

struct ToothCompliance {
  double bending = 0.0;  // m/N
  double shear = 0.0;
  double axial = 0.0;
  double fillet = 0.0;
  double Total() const { return bending + shear + axial + fillet; }
};

class ToothStiffnessModel {
 public:
  ToothStiffnessModel(const GearSpec& gear, const Material& material);
  // A (virtual) gear with a non-integer tooth count: the normal section of a helical gear is the
  // spur gear of z_n = z / cos^3(beta) teeth (module and pressure angle from `gear`, which must be
  // spur; the helix angle is ignored).
  ToothStiffnessModel(const GearSpec& gear, const Material& material, double teeth);

  // Compliance for a contact at roll distance `roll` along the line of action from this gear's base
  // tangent point (roll = r_b tan(alpha_r) for contact radius r).
  ToothCompliance AtRoll(double roll) const;
  // Compliance for force angle alpha1 (rad).
  ToothCompliance AtForceAngle(double alpha1) const;

  double base_radius() const { return r_b_; }
  double root_radius() const { return r_f_; }
  double half_base_angle() const { return alpha2_; }   // alpha2
  double root_half_angle() const { return theta_f_; }  // theta_f
  double body_ratio() const { return h_f_; }           // h_f = r_f / r_bore
  // Non-empty when the Sainsot fit is used outside the envelope gearnvh trusts.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  double E_, G_, L_;
  double r_b_, r_f_, alpha2_, alpha_start_;
  double straight_half_thickness_ = 0.0;  // > 0 when r_b > r_f
  double x_root_straight_ = 0.0;          // start of the straight part on the centre line
  double theta_f_, h_f_;
  double fillet_L_, fillet_M_, fillet_P_, fillet_Q_;
  GaussLegendreRule rule_;
  std::vector<std::string> warnings_;
};

// Hertzian contact stiffness of a line contact, load-independent form (Yang & Sun 1985):
//   k_h = pi L / (2 [(1 - nu1^2)/E1 + (1 - nu2^2)/E2])  (= pi E L / (4 (1 - nu^2)) for equal
//   materials).
double HertzContactStiffness(const Material& a, const Material& b, double face_width);

}  // namespace gearnvh
