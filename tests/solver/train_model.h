// A gear train built for the solver tests: spec, model and tier-1 tables in one object.
#pragma once

#include <utility>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh::testing {

struct TrainModel {
  TrainSpec spec;
  GearTrain train;
  TrainTables tables;
  explicit TrainModel(TrainSpec s, TrainTableOptions options = {})
      : spec(std::move(s)),
        train(BuildGearTrain(spec)),
        tables(BuildTrainTables(spec, train, options)) {}
};

}  // namespace gearnvh::testing
