// A gearbox taken through model -> reduction -> solver tables (test helper).
#pragma once

#include <utility>

#include "gearnvh/solver/segment_tables.h"

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

}  // namespace gearnvh::testing
