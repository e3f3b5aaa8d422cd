// A gear train built for the solver tests: spec, model and tier-1 tables in one object.
#pragma once

#include <Eigen/Dense>
#include <catch2/catch.hpp>
#include <utility>
#include <vector>

#include "gearnvh/model/gear_train.h"
#include "gearnvh/solver/segment_tables.h"
#include "gearnvh/solver/train_reference.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
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

// The linear periodic steady state of a train held in drive contact on every mesh, the reference
// of the permanent-contact tests: the grid segments of one common period, their propagators
// expm(A h) R from dense Pade of an independent assembly (train_reference.h; R holds the input
// slot at the segment's mean excitation, as the stepper does), the period map P, and its fixed
// point by a complete-orthogonal solve of (I - P) y = p on the full elastic block (the free
// rotation's position is its one null direction and moves no TE).
struct LinearPeriodicState {
  struct Piece {
    double start = 0.0, h = 0.0;
    Eigen::MatrixXd map;  // expm(A h) R
  };
  std::vector<Piece> pieces;  // one common period from t = 0
  Eigen::MatrixXd period_map;
  Eigen::VectorXd z;  // the orbit's state at a period start (constant slot 1)
};

inline LinearPeriodicState DriveContactPeriodicState(const TrainTables& t) {
  const int n = t.n, m = t.m;
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  LinearPeriodicState out;
  out.period_map = Eigen::MatrixXd::Identity(m, m);
  for (TrainGrid grid(t); grid.start() < t.common_period * (1.0 - 1e-12); grid.Next()) {
    const double h = grid.end() - grid.start();
    Eigen::MatrixXd R = Eigen::MatrixXd::Identity(m, m);
    R(t.input_slot(), t.input_slot()) = 0.0;
    R(t.input_slot(), t.constant_slot()) = t.MeanExcitation(grid.start(), h);
    const Eigen::MatrixXd A = AssembleTrainGenerator(t, grid.segments(), drive);
    out.pieces.push_back({grid.start(), h, BalancedExpm(A, h, n, ReferenceFrequency(A, n)) * R});
    out.period_map = out.pieces.back().map * out.period_map;
  }
  const Eigen::MatrixXd& P = out.period_map;
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(2 * n, 2 * n);
  out.z = Eigen::VectorXd::Zero(m);
  out.z.head(2 * n) = (I - P.topLeftCorner(2 * n, 2 * n))
                          .completeOrthogonalDecomposition()
                          .solve(P.block(0, t.constant_slot(), 2 * n, 1));
  out.z[t.constant_slot()] = 1.0;
  return out;
}

// A run from the static state to `end` (s) with certified jumps on or off, recorded (32 samples
// per cycle) from `record_start`: its summary, statistics and final state.
struct RecordedTrainRun {
  TrainStepperSummary summary;
  TrainStatistics stats;
  Eigen::VectorXd state;
};

inline RecordedTrainRun RunTrainFromStatic(const TrainTables& t, bool jumps, double record_start,
                                           double end) {
  const auto [z0, states0] = TrainStaticState(t);
  TrainStepperOptions options;
  options.jumps = jumps;
  TrainStepper stepper(t, options, z0, states0);
  TrainRecorder recorder(t, 32, record_start);
  REQUIRE(stepper.Run(end, &recorder));
  return {stepper.summary(), recorder.Result(), stepper.state()};
}

}  // namespace gearnvh::testing
