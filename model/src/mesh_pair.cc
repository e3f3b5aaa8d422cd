#include "gearnvh/model/mesh_pair.h"

#include <algorithm>
#include <cmath>

namespace gearnvh {

GearSpec TransverseSection(const GearSpec& gear) {
  if (gear.helix_angle == 0.0) return gear;
  GearSpec t = gear;
  const double c = std::cos(gear.helix_angle);
  t.module = gear.module / c;
  t.pressure_angle = std::atan(std::tan(gear.pressure_angle) / c);
  // The same lengths in units of the transverse module.
  t.addendum_coefficient = gear.addendum_coefficient * c;
  t.dedendum_coefficient = gear.dedendum_coefficient * c;
  t.profile_shift = gear.profile_shift * c;
  t.helix_angle = 0.0;
  return t;
}

MeshPair PairOf(const GearboxSpec& spec) {
  MeshPair p;
  p.a = TransverseSection(spec.pinion);
  p.b = TransverseSection(spec.wheel);
  p.normal_a = spec.pinion;
  p.normal_b = spec.wheel;
  p.helix_angle = spec.pinion.helix_angle;
  p.normal_module = spec.pinion.module;
  p.face_width = std::min(spec.pinion.face_width, spec.wheel.face_width);
  p.hand_a = spec.pinion.hand;
  p.mesh = spec.mesh;
  p.material_a = spec.MaterialOf(spec.pinion);
  p.material_b = spec.MaterialOf(spec.wheel);
  p.speed_a = spec.operating.speed;
  p.transmitted_torque = spec.WheelTorque();
  p.path_a = "gears.pinion";
  p.path_b = "gears.wheel";
  p.path_mesh = "mesh";
  return p;
}

}  // namespace gearnvh
