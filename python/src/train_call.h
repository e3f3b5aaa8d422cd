// The shape every train function of the module shares (train.cc, train_analyses.cc).
#pragma once

#include <string>

#include "binding_support.h"
#include "gearbox.h"

namespace gearnvh::python {

// Plans a train command from the keyword arguments (`plan(spec, source)`), then runs it
// (`run(planned, spec, source, control)`) on a worker thread that `progress` reports on and
// Ctrl-C interrupts; errors of either step name the train's source and the module's keywords.
template <typename Plan, typename Run>
auto PlanAndRunOnTrain(const Train& train, Plan&& plan, Run&& run, const py::object& progress) {
  const TrainSpec spec = train.spec();
  const std::string source = train.source();
  auto planned = NamingSource(source, [&] { return plan(spec, source); });
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] { return run(planned, spec, source, control); });
      },
      progress);
}

}  // namespace gearnvh::python
