// A gearbox taken through model -> reduction -> solver tables (test helper).
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <utility>
#include <vector>

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

// The median |g'| of the events (0 when there are none).
template <typename Record, typename Rate>
double TypicalRate(const std::vector<Record>& events, Rate rate_of) {
  std::vector<double> rates;
  for (const Record& e : events) rates.push_back(std::abs(rate_of(e)));
  if (rates.empty()) return 0.0;
  std::nth_element(rates.begin(), rates.begin() + rates.size() / 2, rates.end());
  return rates[rates.size() / 2];
}

// max(1, v_typ / |g'|): how much less sharply a crossing slower than the typical one is placed (a
// gap error delta moves a crossing by delta / |g'|).
inline double SlowCrossingFactor(double rate, double v_typ) {
  rate = std::abs(rate);
  return rate > 0.0 ? std::max(1.0, v_typ / rate) : 1.0;
}

// Two runs log the same events (from, to, in order) with every time within `tolerance` s, scaled
// for a crossing slower than the run's typical one (SlowCrossingFactor).
inline void CheckSameEvents(const Trajectory& a, const Trajectory& b, double tolerance) {
  REQUIRE(a.events.size() == b.events.size());
  const double v_typ = TypicalRate(a.events, [](const EventRecord& e) { return e.gap_rate; });
  for (size_t i = 0; i < a.events.size(); ++i) {
    const double dt = std::abs(a.events[i].time - b.events[i].time);
    INFO("event " << i << " at " << a.events[i].time << " s: times differ by " << dt
                  << " s, gap rate " << a.events[i].gap_rate << " m/s (typical " << v_typ << ")");
    CHECK(a.events[i].from == b.events[i].from);
    CHECK(a.events[i].to == b.events[i].to);
    CHECK(dt <= tolerance * SlowCrossingFactor(a.events[i].gap_rate, v_typ));
  }
}

}  // namespace gearnvh::testing
