// One mesh of a gearbox as the mesh-level model sees it: its two gears (gear a drives in the
// drive-flank sign convention; a is called the pinion and b the wheel of this mesh) as their
// transverse sections (a helical gear's normal module m_n and pressure angle a_n become
// m_t = m_n / cos(beta), tan(a_t) = tan(a_n) / cos(beta), and the addendum, dedendum and profile
// shift coefficients are rescaled by cos(beta), so every spur formula applies to the section), the
// helix angle, the mesh keys, the gears' materials, the nominal speed of gear a, the mean torque
// the mesh transmits, and the YAML paths of its parts for error messages.
#pragma once

#include <string>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct MeshPair {
  GearSpec a, b;                // transverse sections (helix_angle 0)
  GearSpec normal_a, normal_b;  // the gears as specified (normal module and pressure angle)
  double helix_angle = 0.0;     // beta at the reference cylinder, rad (0: spur)
  double normal_module = 0.0;   // m_n, m
  double face_width = 0.0;      // the common face width b = min(b_a, b_b), m
  Hand hand_a = Hand::kRight;   // gear a's hand (gear b has the other)
  MeshSpec mesh;
  Material material_a, material_b;
  double speed_a = 0.0;             // rad/s, nominal speed of gear a (> 0)
  double transmitted_torque = 0.0;  // N m, mean torque gear b delivers (>= 0): load = T / r_b,b
  // The linear mismatch across the face from the shafts' deflection under the static load, m
  // (signed as MeshSpec::misalignment; 0 for rigid shafts).
  double shaft_misalignment = 0.0;
  std::string path_a, path_b, path_mesh;  // "gears.pinion", "gears.wheel", "mesh"
  bool helical() const { return helix_angle > 0.0; }
};

// The transverse section of a gear (the gear itself when it is spur).
GearSpec TransverseSection(const GearSpec& gear);

// The single mesh of a schema-1 gearbox: the pinion drives the wheel against operating.torque.
MeshPair PairOf(const GearboxSpec& spec);

}  // namespace gearnvh
