// The library's input errors name its own fields and arguments; the app names them as the user
// wrote them: the YAML path on the command line, the keyword in Python (app/src/input_names.h).
#include "input_names.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "gearnvh/model/component_model.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/solver/exact_solver.h"
#include "model/test_specs.h"
#include "support/run_command.h"

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
  const ComponentModel rigid = BuildComponentModel(testing::StandardPair(27, 43));
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

TEST_CASE("failed atlas cells and orbit points name the YAML path the user set",
          "[app][errors][cli]") {
  // The cells and points keep their input errors as text; the commands word them as the error
  // of a whole run is worded (app::UserWording), not at the library's names.
  const std::string exe = GEARNVH_EXE;
  const std::string rattle = std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml";
  const auto atlas = testing::RunCommand(
      exe +
      " atlas --tier 5 --cycles 8 --transient 0 --x operating.speed=700rpm:800rpm:2"
      " --y operating.torque=0.1Nm:0.2Nm:1 " +
      rattle);
  INFO(atlas.out << atlas.err);
  CHECK(atlas.exit_code == 1);
  CHECK(atlas.out.find("failed: analysis.tier: needs flexible shafts") != std::string::npos);

  // Engine order 2.0137 does not repeat with the mesh: no periodic orbit.
  std::ifstream in(rattle);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const size_t at = yaml.find("order: 2,");
  REQUIRE(at != std::string::npos);
  yaml.replace(at, 9, "order: 2.0137,");
  const testing::TempDir dir;
  const auto orbits = testing::RunCommand(exe + " orbits --transient 10 " +
                                          dir.Write("incommensurate.yaml", yaml).string());
  INFO(orbits.out << orbits.err);
  CHECK(orbits.exit_code == 1);
  CHECK(orbits.out.find("failed: operating.excitation: orders must repeat with the mesh") !=
        std::string::npos);
}

}  // namespace
}  // namespace gearnvh
