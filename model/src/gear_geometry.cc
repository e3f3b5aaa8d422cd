#include "gearnvh/model/gear_geometry.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "gearnvh/model/input_error.h"

namespace gearnvh {
double Involute(double alpha) { return std::tan(alpha) - alpha; }

double InverseInvolute(double inv) {
  // Newton on f(a) = tan a - a - inv, f' = tan^2 a; start from Cheng's approximation.
  double a = std::cbrt(3.0 * inv) * (1.0 - 0.4 * std::cbrt(inv * inv));
  if (!(a > 0.0)) a = 1e-3;
  for (int i = 0; i < 50; ++i) {
    const double t = std::tan(a);
    const double step = (t - a - inv) / (t * t);
    a -= step;
    if (std::abs(step) < 1e-15 * a) break;
  }
  return a;
}

GearRadii ComputeGearRadii(const GearSpec& gear) {
  const GearSpec g = TransverseSection(gear);
  GearRadii r;
  r.pitch = 0.5 * g.module * g.teeth;
  r.base = r.pitch * std::cos(g.pressure_angle);
  r.tip = r.pitch + (g.addendum_coefficient + g.profile_shift) * g.module;
  r.root = r.pitch - (g.dedendum_coefficient - g.profile_shift) * g.module;
  return r;
}

PairGeometry ComputePairGeometry(const MeshPair& pair) {
  const GearSpec& p = pair.a;
  const GearSpec& w = pair.b;
  // A mismatch is shown as written: a helical pair's normal module and pressure angle, not its
  // sections' (equal helix angles: the sections match exactly when the normal values do).
  const GearSpec& written_a = pair.helical() ? pair.normal_a : p;
  const GearSpec& written_b = pair.helical() ? pair.normal_b : w;
  if (std::abs(p.module - w.module) > 1e-12 * p.module) {
    throw InputError(
        pair.path_b + ".module", 0, {"{}", {InputError::Length(written_b.module)}},
        {"must equal the module of " + pair.path_a + " ({}): gears in mesh share the module",
         {InputError::Length(written_a.module)}});
  }
  if (std::abs(p.pressure_angle - w.pressure_angle) > 1e-12) {
    throw InputError(pair.path_b + ".pressure_angle", 0,
                     {"{}", {InputError::Angle(written_b.pressure_angle)}},
                     {"must equal the pressure angle of " + pair.path_a +
                          " ({}): gears in mesh share the pressure angle",
                      {InputError::Angle(written_a.pressure_angle)}});
  }
  PairGeometry g;
  g.pinion = ComputeGearRadii(p);
  g.wheel = ComputeGearRadii(w);
  g.gear_ratio = static_cast<double>(w.teeth) / p.teeth;
  const double alpha0 = p.pressure_angle;
  const double a0 = g.pinion.pitch + g.wheel.pitch;
  if (pair.mesh.center_distance) {
    g.center_distance = *pair.mesh.center_distance;
  } else {
    const double x_sum = p.profile_shift + w.profile_shift;
    const double inv_w = Involute(alpha0) + 2.0 * x_sum * std::tan(alpha0) / (p.teeth + w.teeth);
    g.center_distance = a0 * std::cos(alpha0) / std::cos(InverseInvolute(inv_w));
  }
  const double cos_w = (g.pinion.base + g.wheel.base) / g.center_distance;
  if (!(cos_w < 1.0)) {
    throw InputError(pair.path_mesh + ".center_distance", 0,
                     {"{}", {InputError::Length(g.center_distance)}},
                     {"must exceed the sum of base radii ({})",
                      {InputError::Length(g.pinion.base + g.wheel.base)}});
  }
  g.working_pressure_angle = std::acos(cos_w);
  g.base_pitch = std::numbers::pi * p.module * std::cos(alpha0);
  g.line_of_action_length = g.center_distance * std::sin(g.working_pressure_angle);
  const double ap = std::sqrt(g.pinion.tip * g.pinion.tip - g.pinion.base * g.pinion.base);
  const double aw = std::sqrt(g.wheel.tip * g.wheel.tip - g.wheel.base * g.wheel.base);
  g.contact_ratio = (ap + aw - g.line_of_action_length) / g.base_pitch;
  g.contact_start = g.line_of_action_length - aw;
  g.contact_end = ap;
  g.pitch_point = g.pinion.base * std::tan(g.working_pressure_angle);
  if (g.contact_start < 0.0 || g.contact_end > g.line_of_action_length) {
    throw InputError(pair.path_mesh, 0, "",
                     "a tip circle reaches beyond the mating base circle (involute interference); "
                     "reduce addendum_coefficient or profile_shift");
  }
  if (g.contact_ratio < 1.0) {
    // A given centre distance is the likely cause: name it and what it gives.
    if (pair.mesh.center_distance) {
      throw InputError(pair.path_mesh + ".center_distance", 0,
                       {"{}", {InputError::Length(g.center_distance)}},
                       {"gives a transverse contact ratio of " + MessageNumber(g.contact_ratio) +
                            ", must give >= 1 for continuous contact (the standard centre "
                            "distance r_p,a + r_p,b is {})",
                        {InputError::Length(a0)}});
    }
    throw InputError(pair.path_mesh, 0, MessageNumber(g.contact_ratio),
                     "contact ratio must be >= 1 for continuous contact");
  }
  g.mesh_frequency_hz = p.teeth * pair.speed_a / (2.0 * std::numbers::pi);
  g.mesh_period_s = 1.0 / g.mesh_frequency_hz;
  g.face_width = pair.face_width;
  g.helix_angle = pair.helix_angle;
  // sin(beta_b) = sin(beta) cos(a_n), with cos(a_n) from the transverse angle: tan a_n = tan a_t
  // cos beta.
  const double normal_pressure = std::atan(std::tan(alpha0) * std::cos(pair.helix_angle));
  g.base_helix_angle = std::asin(std::sin(pair.helix_angle) * std::cos(normal_pressure));
  g.overlap_ratio = pair.normal_module > 0.0 ? pair.face_width * std::sin(pair.helix_angle) /
                                                   (std::numbers::pi * pair.normal_module)
                                             : 0.0;
  g.total_contact_ratio = g.contact_ratio + g.overlap_ratio;
  return g;
}

const char* TierName(Tier tier) {
  switch (tier) {
    case Tier::kTier1:
      return "tier 1";
    case Tier::kTier2:
      return "tier 2";
    case Tier::kTier3:
      return "tier 3";
    case Tier::kTier4:
      return "tier 4";
    case Tier::kTier5:
      return "N40 full";
    case Tier::kN20Simple:
      return "N20 simple";
    case Tier::kN20Mta:
      return "N20 MTA";
  }
  return "unknown";
}

const char* TorqueOnName(TorqueOn on) { return on == TorqueOn::kWheel ? "wheel" : "pinion"; }

double WholeDepth(const PairGeometry& g) {
  return std::min(g.pinion.tip - g.pinion.root, g.wheel.tip - g.wheel.root);
}

}  // namespace gearnvh
