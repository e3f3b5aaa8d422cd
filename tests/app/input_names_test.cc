// The library's input errors name its own fields and arguments; the app names them as the user
// wrote them: the YAML path on the command line, the keyword in Python (app/src/input_names.h).
#include "input_names.h"

#include <catch2/catch.hpp>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "app/load_error.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gearbox_spec_limits.h"
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

TEST_CASE("a --tier the model cannot have names the flag and its text", "[app][errors][cli]") {
  const std::string exe = GEARNVH_EXE;
  const std::string rattle = std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml";
  for (const char* command : {"simulate", "sweep"}) {
    INFO(command);
    const auto run = testing::RunCommand(exe + " " + command + " --tier 'N40 full' " + rattle);
    INFO(run.err);
    CHECK(run.exit_code == 2);  // a usage error, as a train's
    CHECK(run.err.find("error: " + rattle + ": --tier: needs flexible shafts") !=
          std::string::npos);
    CHECK(run.err.find("got N40 full") != std::string::npos);
    CHECK(run.err.find("analysis.tier") == std::string::npos);
  }
  // From the file: its line and the value written there.
  const testing::TempDir dir;
  const auto file = dir.Write("tier5.yaml", testing::Replace(testing::Example("idle_rattle.yaml"),
                                                             "tier: 1\n", "tier: 5\n"))
                        .string();
  const auto run = testing::RunCommand(exe + " simulate " + file);
  INFO(run.err);
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("tier5.yaml:46: analysis.tier: needs flexible shafts") != std::string::npos);
  CHECK(run.err.find("got '5'") != std::string::npos);
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
      " --y operating.torque=0.1Nm:0.2Nm:2 " +
      rattle);
  INFO(atlas.out << atlas.err);
  CHECK(atlas.exit_code == 1);
  // The tier came from the flag: the flag and the text given, not the file's analysis.tier.
  CHECK(atlas.out.find("failed: --tier: needs flexible shafts (at least 28 interior DOF); this "
                       "model has 12 DOF, got 5") != std::string::npos);
  CHECK(atlas.out.find("analysis.tier") == std::string::npos);

  // A cell's value outside the schema's range is shown as the axis shows it (-10 µm, not the SI
  // -1e-05 the variant holds), as a train's cells are.
  const auto backlash =
      testing::RunCommand(exe +
                          " atlas --json --cycles 8 --transient 0 --x mesh.backlash=-10um:80um:2"
                          " --y operating.speed=800rpm:900rpm:2 " +
                          rattle);
  INFO(backlash.err);
  CHECK(backlash.exit_code == 1);
  const auto cells = nlohmann::json::parse(backlash.out)["cells"];
  CHECK(cells[0]["message"] == "mesh.backlash: must be > 0, got -10 µm");
  CHECK(cells[1]["ok"] == true);
  const auto swept = testing::RunCommand(
      exe + " orbits --json --transient 8 --sweep mesh.backlash=-10um:80um:2 " + rattle);
  INFO(swept.err);
  CHECK(swept.exit_code == 1);
  const auto points = nlohmann::json::parse(swept.out)["points"];
  CHECK(points[0]["message"] == "mesh.backlash: must be > 0, got -10 µm");

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
