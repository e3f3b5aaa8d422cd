// Gear-pair geometry (docs/design.md §2.1, docs/gear-trains.md), all in SI units; a helical pair is
// computed on its transverse section (mesh_pair.h), so the spur formulas below hold with
// transverse quantities.
//
//   r_p = m z / 2,  r_b = r_p cos(alpha0),  r_a = r_p + (h_a* + x) m,  r_f = r_p - (h_f* - x) m
//   p_b = pi m cos(alpha0)
//   centre distance a: given, else the zero-backlash working distance of the shifted pair
//     inv(alpha_w) = inv(alpha0) + 2 (x1 + x2) tan(alpha0) / (z1 + z2),  a = a0
//     cos(alpha0)/cos(alpha_w) (for x1 + x2 = 0 this is the standard a0 = r_p1 + r_p2)
//   alpha_w = acos((r_b1 + r_b2) / a)
//   contact ratio eps = [sqrt(r_a1^2 - r_b1^2) + sqrt(r_a2^2 - r_b2^2) - a sin(alpha_w)] / p_b
//   mesh period T_m = 2 pi / (z1 Omega1), mesh frequency f_m = z1 Omega1 / (2 pi)
// Line of action coordinates: T1 and T2 are the tangency points on the base circles, |T1T2| =
// a sin(alpha_w). Contact starts where the wheel tip circle cuts the line (s_start from T1) and
// ends where the pinion tip circle cuts it (s_end), s_end - s_start = eps p_b.
#pragma once

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/mesh_pair.h"

namespace gearnvh {

struct GearRadii {
  double pitch = 0.0;  // r_p
  double base = 0.0;   // r_b
  double tip = 0.0;    // r_a
  double root = 0.0;   // r_f
};

struct PairGeometry {
  GearRadii pinion;
  GearRadii wheel;
  double center_distance = 0.0;         // a, m
  double working_pressure_angle = 0.0;  // alpha_w, rad
  double base_pitch = 0.0;              // p_b, m
  double contact_ratio = 0.0;           // eps
  double line_of_action_length = 0.0;   // |T1 T2| = a sin(alpha_w), m
  double contact_start = 0.0;           // s at start of active contact, measured from T1, m
  double contact_end = 0.0;             // s at end of active contact, m
  double pitch_point = 0.0;             // s of the pitch point = r_b1 tan(alpha_w), m
  double gear_ratio = 0.0;              // z2 / z1
  double mesh_frequency_hz = 0.0;       // at the operating speed
  double mesh_period_s = 0.0;
  // Helical pairs (docs/gear-trains.md; all 0 or equal to the transverse values for spur gears): the helix
  // angle beta, the base helix angle beta_b (sin beta_b = sin beta cos a_n), the common face width,
  // the overlap ratio eps_beta = b sin beta / (pi m_n) and the total contact ratio
  // eps_gamma = eps_alpha + eps_beta (contact_ratio above is the transverse eps_alpha).
  double helix_angle = 0.0, base_helix_angle = 0.0;
  double face_width = 0.0;
  double overlap_ratio = 0.0;
  double total_contact_ratio = 0.0;
};

// Radii of a gear (of its transverse section when it is helical).
GearRadii ComputeGearRadii(const GearSpec& gear);

// Geometry of one mesh; "pinion" and "wheel" are the mesh's gears a and b. Throws InputError (the
// mesh's or a gear's path) when the pair cannot mesh: contact ratio < 1, tip beyond the other
// gear's base circle, centre distance too small, modules or pressure angles that differ.
PairGeometry ComputePairGeometry(const MeshPair& pair);
// The shallower gear's whole depth r_a - r_f (m): how far the flanks can move into each other.
double WholeDepth(const PairGeometry& g);
inline PairGeometry ComputePairGeometry(const GearboxSpec& spec) {
  return ComputePairGeometry(PairOf(spec));
}

// inv(alpha) = tan(alpha) - alpha, and its inverse by Newton's method.
double Involute(double alpha);
double InverseInvolute(double inv);

}  // namespace gearnvh
