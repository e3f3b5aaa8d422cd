// The shape the module's calls on a gearbox or a train share: the spec and source taken from the
// Python object, the keywords made into the command line's options, the app's plan on the calling
// thread and its run on a worker thread (train.cc, train_atlas.cc, train_orbits_tiers.cc,
// validation.cc, module.cc).
#pragma once

#include <optional>
#include <string>

#include "binding_support.h"
#include "gearbox.h"

namespace gearnvh::python {

// Runs `run(spec, source, control)` on a worker thread that `progress` reports on and Ctrl-C
// interrupts (RunInterruptible), on a copy of the spec of `model` (a Gearbox or a Train); its
// errors name the source and the module's keywords (NamingSource).
template <typename Model, typename Run>
auto RunOnModel(const Model& model, Run&& run, const py::object& progress) {
  const auto spec = model.spec();
  const std::string source = model.source();
  return RunInterruptible(
      [&](CallControl& control) {
        return NamingSource(source, [&] { return run(spec, source, control); });
      },
      progress);
}

// Plans a train command from the keyword arguments (`plan(spec, source)`) on the calling thread,
// then runs it (`run(planned, spec, source, control)`) as RunOnModel; errors of either step name
// the train's source and the module's keywords.
template <typename Plan, typename Run>
auto PlanAndRunOnTrain(const Train& train, Plan&& plan, Run&& run, const py::object& progress) {
  auto planned = NamingSource(train.source(), [&] { return plan(train.spec(), train.source()); });
  return RunOnModel(
      train,
      [&](const TrainSpec& spec, const std::string& source, CallControl& control) {
        return run(planned, spec, source, control);
      },
      progress);
}

// A train command's options with the keywords every one shares: the file (`source`), tier= and
// method= (ParseMethod: InputError naming `method`).
template <typename Options>
Options TrainCommandOptions(const std::string& source, const py::object& tier,
                            const std::string& method) {
  Options options;
  options.file = source;
  options.tier = TierText(tier);
  options.method = app::ParseMethod(method, "method");
  return options;
}

// The same with the run length: cycles= and transient= (None: the command's default).
template <typename Options>
Options TrainCommandOptions(const std::string& source, const py::object& tier,
                            const std::string& method, std::optional<long> cycles,
                            std::optional<long> transient) {
  auto options = TrainCommandOptions<Options>(source, tier, method);
  options.cycles = cycles;
  options.transient = transient;
  return options;
}

}  // namespace gearnvh::python
