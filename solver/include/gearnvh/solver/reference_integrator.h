// Brute-force reference for validation and benchmarks (docs/design.md §4.6): SUNDIALS CVODE (BDF, dense
// direct solver with the exact Jacobian A) on the same piecewise model z' = A_{j,sigma} z, stopping
// at every segment boundary (tstop), with CVODE's rootfinding on the walls of the current contact
// state. At a root the state switches and CVODE is re-initialised. CVODE runs in one-step mode and
// its interpolant over each internal step gives the dense output: samples at uniform times
// (samples_per_cycle per mesh cycle from t = 0) and the statistics of the trajectory (8-point
// Gauss-Legendre per step, which integrates the step's polynomial and its square exactly;
// extrema from 16 points per step refined by the parabola through the best three) — a dense
// reference for the exact recorder, computed independently of it. Accuracy is set by rtol/atol;
// nothing here is exact — it is the independent yardstick the exact solver is checked against.
#pragma once

#include <atomic>
#include <string>

#include "gearnvh/solver/exact_solver.h"

namespace gearnvh {

struct ReferenceOptions {
  long cycles = 20;              // >= 1 (recorded from the start)
  double rtol = 1e-12;           // in (0, 1e-3]
  double atol_position = 1e-18;  // m or rad, > 0
  double atol_velocity = 1e-14;  // m/s or rad/s, > 0
  long max_events = 100000;      // >= 1
  int samples_per_cycle = 32;    // uniform output samples per mesh cycle (CVODE's interpolant)
  // Polled between CVODE's steps: RunCancelled once set (SolverOptions::cancel). Not owned.
  const std::atomic<bool>* cancel = nullptr;
  void Validate() const;
};

enum class ReferenceStatus { kSuccess, kSolverFailure, kTooManyEvents };

struct ReferenceResult {
  ReferenceStatus status = ReferenceStatus::kSuccess;
  std::string message;
  Trajectory trajectory;  // uniform samples, events, dense statistics
  long steps = 0;         // CVODE internal steps
  double wall_s = 0.0;
};

ReferenceResult SimulateReference(const SegmentTables& tables, const Eigen::VectorXd& z0,
                                  ContactState state0, const ReferenceOptions& options);

}  // namespace gearnvh
