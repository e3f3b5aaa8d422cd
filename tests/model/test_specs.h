// Hand-built GearboxSpecs for model-level tests (no YAML).
#pragma once

#include <numbers>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh::testing {

// A standard 20-degree steel spur pair, module m, z1:z2, face width b, no shafts.
inline GearboxSpec StandardPair(int z1, int z2, double module = 2e-3, double face = 15e-3) {
  GearboxSpec s;
  s.name = "standard pair";
  s.materials["steel"] = Material{206e9, 0.3, 7850.0};
  for (GearSpec* g : {&s.pinion, &s.wheel}) {
    g->module = module;
    g->pressure_angle = 20.0 * std::numbers::pi / 180.0;
    g->face_width = face;
    g->material = "steel";
  }
  s.pinion.teeth = z1;
  s.wheel.teeth = z2;
  s.pinion.bore_diameter = 0.4 * module * z1;
  s.wheel.bore_diameter = 0.4 * module * z2;
  s.mesh.backlash = 100e-6;
  s.operating.speed = 800.0 * 2.0 * std::numbers::pi / 60.0;
  s.operating.torque = 0.5;
  return s;
}

}  // namespace gearnvh::testing
