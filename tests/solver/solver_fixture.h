// A gearbox taken through model -> reduction -> solver tables (test helper).
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <utility>

#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/segment_tables.h"
#include "model/test_specs.h"

namespace gearnvh::testing {

struct SolverSetup {
  GearboxSpec spec;
  ComponentModel model;
  ReducedModel reduced;
  SegmentTables tables;
  SolverSetup(GearboxSpec s, Tier tier)
      : spec(std::move(s)),
        model(BuildComponentModel(spec)),
        reduced(ReduceModel(model, tier)),
        tables(BuildSegmentTables(model, reduced, spec)) {}
};

// The idle-rattle gearbox of examples/idle_rattle.yaml, built in code.
inline GearboxSpec IdleRattleSpec(double amplitude = 1500.0) {
  GearboxSpec s = StandardPair(27, 43, 2e-3, 15e-3);
  s.pinion.bore_diameter = 25e-3;
  s.wheel.bore_diameter = 30e-3;
  s.pinion.inertia = 5e-3;
  s.mesh.friction_coefficient = 0.05;
  s.operating.torque = 0.2;
  s.operating.excitation = {{2.0, amplitude, 0.0}};
  return s;
}

// Two runs log the same events (from, to, in order) with every time within `tolerance` s.
inline void CheckSameEvents(const Trajectory& a, const Trajectory& b, double tolerance) {
  REQUIRE(a.events.size() == b.events.size());
  for (size_t i = 0; i < a.events.size(); ++i) {
    INFO("event " << i << " at " << a.events[i].time << " s");
    CHECK(a.events[i].from == b.events[i].from);
    CHECK(a.events[i].to == b.events[i].to);
    CHECK(std::abs(a.events[i].time - b.events[i].time) <= tolerance);
  }
}

}  // namespace gearnvh::testing
