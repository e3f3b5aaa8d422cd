#include "gearnvh/nvh/orbit_scan.h"

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/count_text.h"
#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

void OrbitScanOptions::Validate() const {
  if (period < 1) {
    throw InputError("OrbitScanOptions.period", 0, std::to_string(period), "must be >= 1");
  }
  if (transient_cycles < 0) {
    throw InputError("OrbitScanOptions.transient_cycles", 0, std::to_string(transient_cycles),
                     "must be >= 0");
  }
  if (settled_starts < 1) {
    throw InputError("OrbitScanOptions.settled_starts", 0, std::to_string(settled_starts),
                     "must be >= 1");
  }
}

std::vector<OrbitScanPoint> ScanPeriodicOrbits(const GearboxSpec& base,
                                               const std::optional<AtlasAxis>& sweep,
                                               const OrbitScanOptions& options,
                                               const OrbitScanProgress& progress) {
  options.Validate();
  const int points = sweep ? sweep->range.points : 1;
  std::vector<OrbitScanPoint> out(static_cast<size_t>(points));
  std::optional<Eigen::VectorXd> previous;
  for (int i = 0; i < points; ++i) {
    OrbitScanPoint& p = out[static_cast<size_t>(i)];
    try {
      ThrowIfCancelled(options.cancel);
      GearboxSpec spec = base;
      if (sweep) {
        p.value = AxisValue(*sweep, i);
        SetParameter(spec, sweep->parameter, p.value);
        ValidateGearboxSpec(spec);
      }
      const OperatingPointModel op = BuildOperatingPointModel(spec, options.tier, options.cancel);
      const SegmentTables& tables = op.tables;
      PeriodicOrbitOptions orbit_options;
      orbit_options.period = options.period;
      orbit_options.solver.events = options.events;
      orbit_options.solver.method = SolverMethod::kStepped;
      orbit_options.solver.cancel = options.cancel;
      p.ok = true;
      if (previous) {
        p.orbit = FindPeriodicOrbit(tables, *previous, orbit_options);
        if (p.orbit.info == PeriodicOrbit::Info::kConverged) p.start = "continuation";
      }
      if (p.start.empty()) {
        // Settled guesses at phase 0 of the period.
        const long period = options.period * BasePeriodCycles(tables);
        const long settle = (options.transient_cycles + period - 1) / period * period;
        const auto [z0, state0] = StaticInitialState(tables);
        ExactStepper stepper(tables, orbit_options.solver, z0, state0, 0, 0);
        if (settle > 0 && !stepper.Run(settle, false)) {
          p.message = stepper.summary().message;
          p.ok = false;
        }
        for (int k = 0; p.ok && k < options.settled_starts; ++k) {
          if (k > 0 && !stepper.Run(period, false)) {
            p.message = "the stepper stopped while settling: " + stepper.summary().message;
            p.ok = false;
            break;
          }
          PeriodicOrbit trial = FindPeriodicOrbit(tables, stepper.state(), orbit_options);
          const bool converged = trial.info == PeriodicOrbit::Info::kConverged;
          if (k == 0 || converged) p.orbit = std::move(trial);
          if (converged) {
            p.start = "settled run + " + Count(k, "period", "periods");
            break;
          }
        }
      }
      // A stepper that stopped while shooting (out of range, too many events) fails the point.
      if (p.start.empty() && p.ok && p.orbit.info == PeriodicOrbit::Info::kSolverFailed) {
        p.message = p.orbit.message;
        p.ok = false;
      }
      if (p.start.empty()) {
        previous.reset();
        if (p.ok) p.message = p.orbit.message;
      } else {
        previous = p.orbit.z;
        p.message = p.orbit.message;
      }
    } catch (const InputError& e) {
      p.ok = false;
      std::vector<ParameterValue> set;
      if (sweep) set.push_back({sweep->parameter, p.value});
      p.message = options.input_error_message ? options.input_error_message(e, set) : e.what();
      previous.reset();
    } catch (const std::exception& e) {
      p.ok = false;
      p.message = e.what();
      previous.reset();
    }
    if (progress) progress(i + 1, points);
  }
  return out;
}

}  // namespace gearnvh
