// Brute-force reference for gear trains (docs/design.md §4.6, §11): SUNDIALS CVODE (BDF, dense
// direct solver with the exact Jacobian) on the same piecewise model as TrainStepper, with its own
// assembly of each tuple's generator (from TrainTables' per-mesh data, not the stepper's cache),
// stopping at every boundary of the union grid (TrainGrid) and with CVODE's rootfinding on both
// gaps of every mesh; only crossings in a wall's triggering direction switch that mesh's state, and
// a state found outside a wall at a grid boundary switches at once (as the stepper). Uniform
// samples of every mesh's TE come from CVODE's interpolant. Nothing here is exact: it is the
// independent yardstick of the validation tests, its accuracy set by rtol/atol.
#pragma once

#include <Eigen/Dense>
#include <atomic>
#include <string>
#include <vector>

#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

struct TrainReferenceOptions {
  double end_time = 0.01;        // s, > 0
  double rtol = 1e-12;           // in (0, 1e-3]
  double atol_position = 1e-18;  // rad, > 0
  double atol_velocity = 1e-14;  // rad/s, > 0
  long max_events = 100000;      // >= 1
  double sample_interval = 0.0;  // s: TE samples at k * sample_interval (0: none)
  // Polled between CVODE's steps: RunCancelled once set (SolverOptions::cancel). Not owned.
  const std::atomic<bool>* cancel = nullptr;
  void Validate() const;
};

struct TrainReferenceEvent {
  int mesh = 0;
  double time = 0.0;
  ContactState from = ContactState::kFree, to = ContactState::kFree;
};

struct TrainReferenceResult {
  bool success = true;
  std::string message;
  std::vector<TrainReferenceEvent> events;
  std::vector<double> sample_times;
  Eigen::MatrixXd te;  // samples x contacts (TrainTables::meshes): m, a coupling stage's twist rad
  Eigen::VectorXd final_state;
  std::vector<ContactState> final_states;
  long steps = 0;
};

// The generator of one tuple, assembled from the header maths of train_tables.h.
Eigen::MatrixXd AssembleTrainGenerator(const TrainTables& tables, const std::vector<int>& segments,
                                       const std::vector<ContactState>& states);

TrainReferenceResult SimulateTrainReference(const TrainTables& tables, const Eigen::VectorXd& z0,
                                            const std::vector<ContactState>& states0,
                                            const TrainReferenceOptions& options);

}  // namespace gearnvh
