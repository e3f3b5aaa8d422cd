// The loader tests' base gear train in YAML (schema gearnvh/2) and the helpers that edit it and
// catch what the loader refuses (train_loader_test.cc, train_input_rules_test.cc).
#pragma once

#include <catch2/catch.hpp>
#include <stdexcept>
#include <string>

#include "app/load_error.h"  // Replace, for the tests that include this file
#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::testing {

// Three rigid shafts a -> b -> c: g1 (23) drives g2 (41) on b, g3 (19) on b drives g4 (37) on c.
inline const std::string kThreeShaftTrainYaml = R"(schema: gearnvh/2
name: base train
materials:
  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}
shafts:
  a: {inertia: 2e-3 kg*m^2}
  b: {inertia: 3e-3 kg*m^2}
  c: {inertia: 1e-3 kg*m^2}
gears:
  g1: {shaft: a, teeth: 23, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g2: {shaft: b, teeth: 41, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g3: {shaft: b, teeth: 19, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g4: {shaft: c, teeth: 37, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
meshes:
  - {gears: [g1, g2], backlash: 100 um}
  - {gears: [g3, g4], backlash: 100 um}
operating:
  speed: {shaft: a, value: 1000 rpm}
  loads:
    - {on: c, torque: 1 N*m}
  excitation:
    - {order: 2, amplitude: 500 rad/s^2}
analysis:
  cycles: 50
  transient_cycles: 10
  speed_sweep: {from: 800 rpm, to: 1200 rpm, points: 2}
)";

// `text` with the first `from` replaced by `to`; std::logic_error when `from` is not there (usable
// outside a test case, in static initialisation).
inline std::string ReplaceFirst(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("not in the text: " + from);
  return text.replace(at, from.size(), to);
}

// kThreeShaftTrainYaml with a third mesh: g5 (31 teeth) turns loose on c, driven by g6 (25) on
// b, with a drag torque (meshes[2], loads[1]). Lines up to the gears are those of the base.
inline std::string ThreeShaftTrainWithLooseGearYaml() {
  std::string text = ReplaceFirst(
      kThreeShaftTrainYaml,
      "  g4: {shaft: c, teeth: 37, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, "
      "material: steel}\n",
      "  g4: {shaft: c, teeth: 37, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, "
      "material: steel}\n"
      "  g6: {shaft: b, teeth: 25, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, "
      "material: steel}\n"
      "  g5: {shaft: c, mounting: loose, teeth: 31, module: 2 mm, face_width: 15 mm, "
      "bore_diameter: 30 mm, material: steel}\n");
  text = ReplaceFirst(
      text, "  - {gears: [g3, g4], backlash: 100 um}\n",
      "  - {gears: [g3, g4], backlash: 100 um}\n  - {gears: [g6, g5], backlash: 100 um}\n");
  return ReplaceFirst(text, "    - {on: c, torque: 1 N*m}\n",
                      "    - {on: c, torque: 1 N*m}\n    - {on: g5, torque: 0.2 N*m}\n");
}

// The error the loader throws for `text`; fails the test when it accepts it.
inline InputError LoaderErrorOf(const std::string& text) {
  try {
    config::LoadAnyGearboxFromString(text, "t.yaml");
  } catch (const InputError& e) {
    return e;
  }
  FAIL("accepted");
  throw std::logic_error("unreachable");
}

}  // namespace gearnvh::testing
