#include "gearnvh/model/mesh_pair.h"

namespace gearnvh {

MeshPair PairOf(const GearboxSpec& spec) {
  MeshPair p;
  p.a = &spec.pinion;
  p.b = &spec.wheel;
  p.mesh = &spec.mesh;
  p.material_a = &spec.MaterialOf(spec.pinion);
  p.material_b = &spec.MaterialOf(spec.wheel);
  p.speed_a = spec.operating.speed;
  p.transmitted_torque = spec.WheelTorque();
  p.path_a = "gears.pinion";
  p.path_b = "gears.wheel";
  p.path_mesh = "mesh";
  return p;
}

}  // namespace gearnvh
