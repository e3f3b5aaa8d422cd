// Hand-built GearboxSpecs for model-level tests (no YAML).
#pragma once

#include <numbers>

#include "gearnvh/model/gear_geometry.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/mesh_pair.h"
#include "gearnvh/model/mesh_segmentation.h"
#include "gearnvh/model/mesh_stiffness.h"

namespace gearnvh::testing {

inline constexpr double kRpm = 2.0 * std::numbers::pi / 60.0;  // rad/s per rpm
inline constexpr double kDeg = std::numbers::pi / 180.0;       // rad per degree

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

// A 31:47 pair (module 3 mm, face 30 mm) on two flexible shafts with bearings and driveline
// inertias, ~50 nodes at 10 mm elements: the shape of examples/flexible_shafts.yaml, at 200 N m.
inline GearboxSpec FlexibleShaftsPair(double element_length = 0.01) {
  GearboxSpec spec = StandardPair(31, 47, 3e-3, 30e-3);
  spec.operating.torque = 200.0;
  for (int s = 0; s < 2; ++s) {
    ShaftSpec shaft;
    shaft.material = "steel";
    shaft.segments = {{0.06, 0.03, 0.0}, {0.08, 0.035, 0.0}, {0.1, 0.03, 0.0}};
    shaft.gear_at = s == 0 ? 0.1 : 0.13;
    shaft.bearings = {{0.01, 3e8, 1e8, 0.0, 500.0}, {0.23, 3e8, 0.0, 0.0, 500.0}};
    shaft.inertias = {{s == 0 ? 0.0 : 0.24, 0.02, 0.01}};
    shaft.element_length = element_length;
    (s == 0 ? spec.input_shaft : spec.output_shaft) = shaft;
  }
  return spec;
}

// The mesh stiffness summary of a pair spec, as the model builders make it (default sampling,
// the spec's segments per cycle).
inline MeshStiffnessSummary MeshSummaryOf(const GearboxSpec& spec) {
  const MeshPair pair = PairOf(spec);
  const PairGeometry g = ComputePairGeometry(pair);
  return SummarizeMeshCycle(
      ComputeMeshCycle(pair, g), g,
      SegmentMeshCycle(pair, MeshEvaluator(pair, g), spec.analysis.segments_per_cycle));
}

}  // namespace gearnvh::testing
