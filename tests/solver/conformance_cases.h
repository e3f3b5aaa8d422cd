// The cases of the event-locator conformance suite (event_locator_test.cc): a single pair on tiers
// 1, 3 and 5 in idle rattle and in a near-grazing impact (solver/event_locator.h, spectral_locator.h: SpectralLocator,
// TaylorLocator, DyadicLocator behind ExactStepper), and a rattling gear train with a loose gear
// and a near-grazing impact of that gear (solver/train_stepper.h: V3, V2, V1 as
// TrainStepperOptions::events). Each case runs any of the three event methods from one start and
// hands back what the suite compares, in the same form for a pair and a train, so the suite's
// checks are written once.
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/solver_options.h"
#include "gearnvh/solver/train_statistics.h"
#include "solver/solver_fixture.h"

namespace gearnvh::testing {

enum class ConformanceCaseId {
  kPairTier1,
  kPairTier1Runout,  // tier 1 rattle with the manufacturing-error input (m = 7)
  kPairTier3,
  kPairTier5,
  kPairGrazing,
  kTrainRattle,
  kTrainGrazing,
};

// One run of an event method over the case's window.
struct ConformanceOutcome {
  std::vector<TrainEventRecord> events;  // in the order located (mesh 0 on a pair)
  // [x; x'] at every cycle end of the window, the free rotation's position removed (r~ x = 0):
  // the pair recentres it at cycle ends, the train once per common period.
  std::vector<Eigen::VectorXd> cycle_ends;
  long drive_impacts = 0, back_impacts = 0, separations = 0, grazing = 0;
};

// The warm stepping of a case: the same trajectory run twice on one stepper (the first run builds
// the tables), allocations counted over the second.
struct AllocationRun {
  long allocations = 0;
  long events = 0;  // of the counted run: the event path was exercised
};

// The tangent a method carries over a window with contact changes, against Richardson-
// extrapolated central differences of the same method's map; columns are the perturbed
// directions. Each column must agree within `bound` of its norm.
struct TangentComparison {
  bool found = false;  // a window fit for finite differences was found
  Eigen::MatrixXd tangent, finite_difference;
  double bound = 0.0;
  std::string detail;  // for the failure message
};

class ConformanceCase {
 public:
  virtual ~ConformanceCase() = default;
  virtual const char* name() const = 0;
  virtual int positions() const = 0;          // n: [x; x'] has 2n rows
  virtual double segment_length() const = 0;  // s: h of the event-time bounds
  // Largest relative difference of the cycle-end positions (and velocities) of two methods.
  virtual double state_bound(bool with_v1) const = 0;
  virtual ConformanceOutcome Run(EventMethod method) const = 0;
  // The case does what it is meant to: rattle on both flanks, or its near-grazing impact at the
  // closed-form gap rate.
  virtual void CheckPurpose(const ConformanceOutcome& outcome) const = 0;
  // Whether `method` keeps its tables across steps (then stepping must not allocate once built).
  virtual bool keeps_tables(EventMethod method) const = 0;
  virtual AllocationRun WarmRun(EventMethod method, bool with_tangent) const = 0;
  virtual TangentComparison CompareTangent(EventMethod method) const = 0;

 protected:
  ConformanceCase() = default;
  ConformanceCase(const ConformanceCase&) = delete;
  ConformanceCase& operator=(const ConformanceCase&) = delete;
};

// Built on first use and kept (the tier-5 reduction is the expensive part).
const ConformanceCase& GetConformanceCase(ConformanceCaseId id);

// The pair cases' models and starts, for the pair-only tests (V3's carry, DoStep alone).
const SolverSetup& PairSetup(ConformanceCaseId id);
struct PairStart {
  Eigen::VectorXd z;
  ContactState state;
  long cycles;
};
PairStart PairStartFor(ConformanceCaseId id);
struct PairRun {
  std::vector<EventRecord> events;
  std::vector<Eigen::VectorXd> cycle_ends;  // the whole state z
  SolverSummary summary;
};
PairRun RunPair(EventMethod method, ConformanceCaseId id,
                double carry_max_error = SolverOptions{}.carry_max_error);

}  // namespace gearnvh::testing
