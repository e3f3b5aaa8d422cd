// Hand-built TrainSpecs for train-level tests (no YAML).
#pragma once

#include <numbers>
#include <string>

#include "gearnvh/model/train_spec.h"
#include "model/test_specs.h"

namespace gearnvh::testing {

inline TrainGear TrainGearOf(const std::string& name, const std::string& shaft, int teeth,
                             Mounting mounting = Mounting::kFixed) {
  TrainGear g;
  g.name = name;
  g.shaft = shaft;
  g.mounting = mounting;
  g.gear = StandardPair(teeth, teeth).pinion;
  g.gear.teeth = teeth;
  g.gear.bore_diameter = 10e-3;
  return g;
}

inline TrainShaft RigidShaft(const std::string& name, double inertia) {
  TrainShaft s;
  s.name = name;
  s.inertia = inertia;
  return s;
}

inline TrainMesh TrainMeshOf(const std::string& a, const std::string& b, double backlash = 100e-6) {
  TrainMesh m;
  m.gear_a = a;
  m.gear_b = b;
  m.mesh.backlash = backlash;
  return m;
}

inline ShaftSpec ElasticShaftSpec(double element_length = 0.01) {
  ShaftSpec shaft;
  shaft.material = "steel";
  shaft.segments = {{0.06, 0.03, 0.0}, {0.08, 0.035, 0.0}, {0.06, 0.03, 0.0}};
  shaft.bearings = {{0.01, 3e8, 1e8, 0.0, 500.0}, {0.19, 3e8, 0.0, 0.0, 500.0}};
  shaft.element_length = element_length;
  return shaft;
}

// `spec` with both gears on the elastic test shafts (pinion at 100 mm, wheel at 130 mm), each
// carrying a lumped inertia of 0.02 kg m^2 polar (at 0 and 190 mm): inertia beyond the gears.
inline GearboxSpec OnElasticShaftsWithInertias(GearboxSpec spec) {
  for (int s = 0; s < 2; ++s) {
    ShaftSpec shaft = ElasticShaftSpec(0.01);
    shaft.gear_at = s == 0 ? 0.1 : 0.13;
    shaft.inertias = {{s == 0 ? 0.0 : 0.19, 0.02, 0.01}};
    (s == 0 ? spec.input_shaft : spec.output_shaft) = shaft;
  }
  return spec;
}

// Input (rigid on two bearings, g1 20 teeth at 40 mm, helical right) -> layshaft (elastic: g2 40
// helical left at 50 mm, g3 18 at 150 mm, g6 25 at 100 mm) -> output (elastic: g4 54 at 60 mm,
// loose g5 30 at 140 mm driven by g6). Two bodies turn against the input, so both mesh senses
// occur.
inline TrainSpec ElasticTwoStage(double element_length = 0.01) {
  TrainSpec t;
  t.name = "elastic two-stage";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  TrainShaft input = RigidShaft("input", 2e-3);
  input.bearings = {{0.0, 3e8, 1e8, 1e3, 500.0}, {0.08, 3e8, 0.0, 1e3, 500.0}};
  TrainShaft layshaft, output;
  layshaft.name = "layshaft";
  layshaft.elastic = ElasticShaftSpec(element_length);
  output.name = "output";
  output.elastic = ElasticShaftSpec(element_length);
  output.elastic->inertias = {{0.19, 0.05, 0.02, 3.0}};
  t.shafts = {input, layshaft, output};
  t.gears = {TrainGearOf("g1", "input", 20),
             TrainGearOf("g2", "layshaft", 40),
             TrainGearOf("g3", "layshaft", 18),
             TrainGearOf("g4", "output", 54),
             TrainGearOf("g5", "output", 30, Mounting::kLoose),
             TrainGearOf("g6", "layshaft", 25)};
  // g6-g5 (55 teeth) shares the layshaft-output centre distance of g3-g4 (72 teeth at 2 mm): a
  // module of 2 x 72 / 55 mm.
  t.gears[4].gear.module = t.gears[5].gear.module = 2e-3 * 72.0 / 55.0;
  const double beta = 15.0 * std::numbers::pi / 180.0;
  t.gears[0].gear.helix_angle = t.gears[1].gear.helix_angle = beta;
  t.gears[0].gear.hand = Hand::kRight;
  t.gears[1].gear.hand = Hand::kLeft;
  t.gears[0].at = 0.04;
  t.gears[1].at = 0.05;
  t.gears[2].at = 0.15;
  t.gears[5].at = 0.10;
  t.gears[3].at = 0.06;
  t.gears[4].at = 0.14;
  t.meshes = {TrainMeshOf("g1", "g2"), TrainMeshOf("g3", "g4"), TrainMeshOf("g6", "g5")};
  t.operating.input_shaft = "input";
  t.operating.speed = 1000.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"output", 30.0}, {"g5", 0.2}};
  return t;
}

// The same train on rigid shafts (tier-1 data only: inertias, no bearings).
inline TrainSpec RigidTwoStage() {
  TrainSpec t = ElasticTwoStage();
  t.name = "rigid two-stage";
  t.shafts = {RigidShaft("input", 5e-3), RigidShaft("layshaft", 1e-3), RigidShaft("output", 0.2)};
  for (TrainGear& g : t.gears) g.at.reset();
  return t;
}

// Input (g1, 20) -> layshaft (g2, 30; g3, 25) -> loose gear g4 (25) idling on the input shaft,
// with a load on the layshaft and a drag on g4: a small rattling train (`excitation` rad/s^2 of
// engine order 2; 0 for none).
inline TrainSpec RattlerTrain(double excitation) {
  TrainSpec t;
  t.name = "rattler";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {RigidShaft("input", 2e-3), RigidShaft("layshaft", 1e-3)};
  t.gears = {TrainGearOf("g1", "input", 20), TrainGearOf("g2", "layshaft", 30),
             TrainGearOf("g3", "layshaft", 25), TrainGearOf("g4", "input", 25, Mounting::kLoose)};
  t.meshes = {TrainMeshOf("g1", "g2"), TrainMeshOf("g3", "g4")};
  t.operating.input_shaft = "input";
  t.operating.speed = 800.0 * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"layshaft", 20.0}, {"g4", 0.05}};
  if (excitation > 0.0) t.operating.excitation = {{2.0, excitation, 0.0}};
  t.analysis.segments_per_cycle = 16;
  return t;
}

// Input (g1, 20) -> layshaft (g2, 40; g3, 20) -> output (g4, 40): two loaded stages.
inline TrainSpec TwoStageTrain(double load, double excitation, double rpm) {
  TrainSpec t;
  t.name = "two-stage";
  t.materials["steel"] = Material{206e9, 0.3, 7850.0};
  t.shafts = {RigidShaft("input", 2e-3), RigidShaft("layshaft", 1e-3), RigidShaft("output", 5e-3)};
  t.gears = {TrainGearOf("g1", "input", 20), TrainGearOf("g2", "layshaft", 40),
             TrainGearOf("g3", "layshaft", 20), TrainGearOf("g4", "output", 40)};
  t.meshes = {TrainMeshOf("g1", "g2"), TrainMeshOf("g3", "g4")};
  t.operating.input_shaft = "input";
  t.operating.speed = rpm * 2.0 * std::numbers::pi / 60.0;
  t.operating.loads = {{"output", load}};
  t.operating.excitation = {{2.0, excitation, 0.0}};
  t.analysis.segments_per_cycle = 16;
  return t;
}

// TwoStageTrain(150 N m, no excitation, 600 rpm) with the layshaft's inertia set (`which` 0), or
// one of its stages alone as a one-mesh train with the same transmitted torque: 1 input ->
// layshaft carrying the output's power (75 N m: the same power at half the output ratio), 2 the
// layshaft as the input at its nominal speed. A massive layshaft decouples the two meshes. No
// engine excitation: it is held at its mean over each grid segment, and the train's grid (the union
// of both meshes' boundaries) is finer than a stage's own, a legitimate difference of the
// piecewise model (first order in the segment length) the decoupling tests are not about.
inline TrainSpec TwoStageAlone(int which, double layshaft_inertia) {
  TrainSpec t = TwoStageTrain(150.0, 0.0, 600.0);
  t.operating.excitation.clear();
  t.shafts[1].inertia = layshaft_inertia;
  if (which == 1) {
    t.shafts = {t.shafts[0], t.shafts[1]};
    t.gears = {t.gears[0], t.gears[1]};
    t.meshes = {t.meshes[0]};
    t.operating.loads = {{"layshaft", 75.0}};
  } else if (which == 2) {
    t.shafts = {t.shafts[1], t.shafts[2]};
    t.gears = {t.gears[2], t.gears[3]};
    t.meshes = {t.meshes[1]};
    t.operating.input_shaft = "layshaft";
    t.operating.speed *= 0.5;
  }
  return t;
}

}  // namespace gearnvh::testing
