// The library's input errors name its own fields and arguments; the app names them as the user
// wrote them: the YAML path on the command line, the keyword in Python (app/src/input_names.h).
#include "input_names.h"

#include <catch2/catch.hpp>
#include <string>

#include "gearnvh/model/component_model.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"

namespace gearnvh {
namespace {

const app::InputNames kPython{.tier = "tier", .cycles = "cycles", .transient = "transient"};

template <typename Throw>
InputError Raised(Throw&& raise) {
  try {
    raise();
  } catch (const InputError& e) {
    return e;
  }
  FAIL("no InputError");
  return InputError("", 0, "", "");
}

TEST_CASE("a tier the model cannot have is named where the user chose it", "[app][errors]") {
  const ComponentModel rigid = BuildComponentModel(StandardPair(27, 43));
  try {
    RequireTierAvailable(rigid, Tier::kTier5);
    FAIL("tier 5 of a rigid-shaft model is available");
  } catch (const InputError& e) {
    CHECK(e.path() == "tier");  // the library's argument, no YAML path
    const InputError cli = app::UserNamed(e);
    CHECK(cli.path() == "analysis.tier");
    CHECK(cli.value() == e.value());
    CHECK(cli.value() == TierName(Tier::kTier5));
    CHECK(cli.rule() == e.rule());
    CHECK(std::string(cli.what()) ==
          "analysis.tier: " + e.rule() + ", got " + std::string(TierName(Tier::kTier5)));
    CHECK(app::UserNamed(e, kPython).path() == "tier");
  }
}

TEST_CASE("the solver's run length is named at analysis.cycles or the keyword", "[app][errors]") {
  SolverOptions options;
  options.cycles = 0;
  const InputError cycles = Raised([&] { options.Validate(); });
  CHECK(cycles.path() == "SolverOptions.cycles");
  CHECK(app::UserNamed(cycles).path() == "analysis.cycles");
  CHECK(app::UserNamed(cycles, kPython).path() == "cycles");
  CHECK(app::UserNamed(cycles).value() == "0");
  CHECK(app::UserNamed(cycles).rule() == "must be >= 1");
  options.cycles = 1;
  options.transient_cycles = -3;
  const InputError transient = Raised([&] { options.Validate(); });
  CHECK(transient.path() == "SolverOptions.transient_cycles");
  CHECK(app::UserNamed(transient).path() == "analysis.transient_cycles");
  CHECK(app::UserNamed(transient, kPython).path() == "transient");
  CHECK(app::UserNamed(transient).value() == "-3");
  // Fields the user does not set keep the library's name.
  options.transient_cycles = 0;
  options.max_events_per_cycle = 0;
  const InputError other = Raised([&] { options.Validate(); });
  CHECK(app::UserNamed(other).path() == "SolverOptions.max_events_per_cycle");
}

TEST_CASE("forcing without a common period and an unreducible structure name the file's keys",
          "[app][errors]") {
  const NoCommonPeriod period;
  CHECK(period.path() == "excitation");
  CHECK(app::UserNamed(period).path() == "operating.excitation");
  CHECK(app::UserNamed(period, kPython).path() == "operating.excitation");
  CHECK(app::UserNamed(period).rule() == period.rule());
  const StructureNotReducible structure("cannot be reduced: a direction no bearing holds");
  CHECK(structure.path() == "structure");
  CHECK(app::UserNamed(structure).path() == "shafts");
  CHECK(app::UserNamed(structure).rule() == "cannot be reduced: a direction no bearing holds");
}

}  // namespace
}  // namespace gearnvh
