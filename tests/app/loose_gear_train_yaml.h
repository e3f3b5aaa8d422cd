// An ordinary rattling 3-mesh train in YAML (schema gearnvh/2): a-b and c-d loaded, e-f with the
// light gear f loose on the output shaft under 0.2 N m of drag; it rattles from the first cycle.
#pragma once

#include <string>

namespace gearnvh::testing {

inline const std::string kLooseGearTrainYaml = R"(schema: gearnvh/2
name: Loose gear rattle
materials:
  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}
shafts:
  input: {inertia: 5e-3 kg*m^2}
  layshaft: {inertia: 1.5e-3 kg*m^2}
  output: {inertia: 0.5 kg*m^2}
gears:
  a: {shaft: input, teeth: 21, module: 2 mm, face_width: 18 mm, bore_diameter: 20 mm, material: steel}
  b: {shaft: layshaft, teeth: 35, module: 2 mm, face_width: 18 mm, bore_diameter: 20 mm, material: steel}
  c: {shaft: layshaft, teeth: 19, module: 2 mm, face_width: 18 mm, bore_diameter: 20 mm, material: steel}
  d: {shaft: output, teeth: 37, module: 2 mm, face_width: 18 mm, bore_diameter: 20 mm, material: steel}
  e: {shaft: layshaft, teeth: 25, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  f: {shaft: output, mounting: loose, teeth: 31, module: 2 mm, face_width: 15 mm, bore_diameter: 30 mm, material: steel}
meshes:
  - {gears: [a, b], backlash: 80 um}
  - {gears: [c, d], backlash: 100 um}
  - {gears: [e, f], backlash: 100 um}
operating:
  speed: {shaft: input, value: 1000 rpm}
  loads:
    - {on: output, torque: 20 N*m}
    - {on: f, torque: 0.2 N*m}
  excitation:
    - {order: 2, amplitude: 1000 rad/s^2}
)";

}  // namespace gearnvh::testing
