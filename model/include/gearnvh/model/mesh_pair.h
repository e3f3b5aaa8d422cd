// One mesh of a gearbox as the mesh-level model sees it: its two gears (gear a drives in the
// drive-flank sign convention; a is called the pinion and b the wheel of this mesh), the mesh keys,
// the gears' materials, the nominal speed of gear a and the mean torque the mesh transmits, and
// the YAML paths of the three parts for error messages. Non-owning: the spec outlives it.
#pragma once

#include <string>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct MeshPair {
  const GearSpec* a = nullptr;
  const GearSpec* b = nullptr;
  const MeshSpec* mesh = nullptr;
  const Material* material_a = nullptr;
  const Material* material_b = nullptr;
  double speed_a = 0.0;             // rad/s, nominal speed of gear a (> 0)
  double transmitted_torque = 0.0;  // N m, mean torque gear b delivers (>= 0): load = T / r_b,b
  std::string path_a, path_b, path_mesh;  // "gears.pinion", "gears.wheel", "mesh"
};

// The single mesh of a schema-1 gearbox: the pinion drives the wheel against operating.torque.
MeshPair PairOf(const GearboxSpec& spec);

}  // namespace gearnvh
