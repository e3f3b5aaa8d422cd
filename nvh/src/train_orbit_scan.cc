#include "gearnvh/nvh/train_orbit_scan.h"

#include <cmath>
#include <optional>

#include "gearnvh/model/count_text.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_tables.h"

namespace gearnvh {

void TrainOrbitScanOptions::Validate() const {
  if (periods < 1) {
    throw InputError("TrainOrbitScanOptions.periods", 0, std::to_string(periods), "must be >= 1");
  }
  if (transient_cycles < 0) {
    throw InputError("TrainOrbitScanOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (settled_starts < 1) {
    throw InputError("TrainOrbitScanOptions.settled_starts", 0, std::to_string(settled_starts),
                     "must be >= 1");
  }
}

std::string TrainOrbitStartText(const TrainOrbitScanPoint& p) {
  switch (p.start) {
    case TrainOrbitScanPoint::Start::kContinuation:
      return "continuation";
    case TrainOrbitScanPoint::Start::kSettled:
      return "settled run + " + Count(p.settled_periods, "period", "periods");
    case TrainOrbitScanPoint::Start::kNone:
      break;
  }
  return "";
}

namespace {

struct Guess {
  Eigen::VectorXd z;
  std::vector<ContactState> states;
};

std::string NotFoundText(const TrainOrbit& o, int tries) {
  if (o.info == TrainOrbit::Info::kSolverFailed) {
    return "the train stepper stopped while shooting: " + o.stop_reason;
  }
  return "Newton shooting did not converge from " + std::to_string(tries) +
         " settled start(s) (last scaled residual " + std::to_string(o.residual) + ")";
}

// Settled guesses: the transient rounded up to whole orbit periods, then one period at a time.
void TrySettledStarts(const TrainTables& tables, const TrainOrbitOptions& orbit_options,
                      const TrainOrbitScanOptions& options, TrainOrbitScanPoint& p) {
  const double period = orbit_options.periods * tables.common_period;
  const double transient =
      static_cast<double>(options.transient_cycles) * tables.meshes.front().period;
  const double settle = std::ceil(transient / period * (1.0 - 1e-12)) * period;
  const auto [z0, states0] = TrainStaticState(tables);
  TrainStepper stepper(tables, orbit_options.stepper, z0, states0);
  if (settle > 0.0 && !stepper.Run(settle)) {
    p.ok = false;
    p.message =
        "the train stepper stopped while settling: " + TrainStepperMessage(stepper.summary());
    return;
  }
  int k = 0;
  for (; k < options.settled_starts; ++k) {
    if (k > 0 && !stepper.Run(settle + k * period)) {
      p.ok = false;
      p.message =
          "the train stepper stopped while settling: " + TrainStepperMessage(stepper.summary());
      return;
    }
    TrainOrbit trial =
        FindTrainPeriodicOrbit(tables, stepper.state(), stepper.states(), orbit_options);
    const bool converged = trial.info == TrainOrbit::Info::kConverged;
    if (k == 0 || converged) p.orbit = std::move(trial);
    if (converged) {
      p.start = TrainOrbitScanPoint::Start::kSettled;
      p.settled_periods = k;
      return;
    }
  }
  p.message = NotFoundText(p.orbit, k);
  // A stepper that stopped (out of range, too many events) is a failed point, not "no orbit".
  if (p.orbit.info == TrainOrbit::Info::kSolverFailed) p.ok = false;
}

}  // namespace

std::vector<TrainOrbitScanPoint> ScanTrainPeriodicOrbits(int count, const TrainVariant& variant,
                                                         const TrainOrbitScanOptions& options,
                                                         const TrainOrbitScanProgress& progress) {
  options.Validate();
  std::vector<TrainOrbitScanPoint> out(static_cast<size_t>(count));
  std::optional<Guess> previous;
  for (int i = 0; i < count; ++i) {
    ThrowIfCancelled(options.cancel);
    TrainOrbitScanPoint& p = out[static_cast<size_t>(i)];
    try {
      const TrainSpec spec = variant(i);
      ValidateTrainSpec(spec);
      const GearTrain train = BuildGearTrain(spec);
      TrainTableOptions table_options;
      table_options.cancel = options.cancel;
      const TrainTables tables = BuildTrainTablesAtTier(spec, train, options.tier, table_options);
      p.common_period = tables.common_period;
      p.ok = true;
      TrainOrbitOptions orbit_options;
      orbit_options.periods = options.periods;
      orbit_options.stepper.events = options.events;
      orbit_options.stepper.cancel = options.cancel;
      if (!(tables.common_period > 0.0)) {
        p.message =
            "the meshes and engine orders have no common period within 1000 input revolutions: "
            "the train has no periodic orbit to shoot for";
      } else {
        if (previous && previous->z.size() == tables.m) {
          p.orbit = FindTrainPeriodicOrbit(tables, previous->z, previous->states, orbit_options);
          if (p.orbit.info == TrainOrbit::Info::kConverged) {
            p.start = TrainOrbitScanPoint::Start::kContinuation;
          }
        }
        if (!p.found()) TrySettledStarts(tables, orbit_options, options, p);
      }
    } catch (const std::exception& e) {
      p.ok = false;
      p.message = e.what();
    }
    previous.reset();
    if (p.found()) previous = Guess{p.orbit.z, p.orbit.states};
    if (progress) progress(i + 1, count);
  }
  return out;
}

}  // namespace gearnvh
