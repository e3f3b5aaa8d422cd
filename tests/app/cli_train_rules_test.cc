// The command line on gear trains (schema gearnvh/2) against the input rules: one rule applied by
// check and simulate alike, errors with the file's line and the value as written, option limits
// equal to the YAML limits, and option errors named once.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "app/loose_gear_train_yaml.h"
#include "app/three_shaft_train_yaml.h"
#include "support/run_command.h"
#include "support/paths.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

using testing::kExe;

// An ordinary rattling 3-mesh train: a-b, c-d loaded, e-f with f loose on the output.
const std::string kTrain = testing::kLooseGearTrainYaml + R"(analysis:
  segments_per_cycle: 32
  cycles: 200
  transient_cycles: 50
  speed_sweep: {from: 800 rpm, to: 1600 rpm, points: 3}
)";

using testing::Replace;

// check and simulate refuse `file` with the same message (exit 1); the message.
std::string RefusedAlike(const std::filesystem::path& file) {
  const auto check = RunCommand(kExe + " check " + file.string());
  const auto simulate = RunCommand(kExe + " simulate " + file.string());
  INFO("check: " << check.err << "simulate: " << simulate.err);
  CHECK(check.exit_code == 1);
  CHECK(simulate.exit_code == 1);
  CHECK(check.err == simulate.err);
  return check.err;
}

TEST_CASE("check and simulate refuse too few segments per cycle alike, at its line",
          "[cli][train]") {
  TempDir dir;
  const auto file =
      dir.Write("seg4.yaml", Replace(kTrain, "segments_per_cycle: 32", "segments_per_cycle: 4"));
  const std::string err = RefusedAlike(file);
  CHECK(err.find("seg4.yaml:28: analysis.segments_per_cycle: must be >= ") != std::string::npos);
  CHECK(err.find("in meshes[0] (a-b), got '4'") != std::string::npos);
}

TEST_CASE("a batch locates each file's post-load error in that file", "[cli][train]") {
  // The same rule broken in two files at different lines, checked in one process.
  TempDir dir;
  const std::string seg4 = Replace(kTrain, "segments_per_cycle: 32", "segments_per_cycle: 4");
  const auto a = dir.Write("a.yaml", seg4);
  const auto b = dir.Write("b.yaml", "# shifted\n# down\n" + seg4);
  const auto run = RunCommand(kExe + " check " + a.string() + " " + b.string());
  INFO(run.err);
  CHECK(run.exit_code == 1);
  CHECK(run.err.find("a.yaml:28: analysis.segments_per_cycle: must be >= ") != std::string::npos);
  CHECK(run.err.find("b.yaml:30: analysis.segments_per_cycle: must be >= ") != std::string::npos);
}

TEST_CASE("a tier the train cannot have is refused at the line of analysis.tier", "[cli][train]") {
  TempDir dir;
  const auto file =
      dir.Write("tier4.yaml", Replace(kTrain, "analysis:\n", "analysis:\n  tier: 4\n"));
  const std::string err = RefusedAlike(file);
  CHECK(err.find("tier4.yaml:28: analysis.tier: tiers 4, 5, N20 simple and N20 MTA need an "
                 "elastic shaft in the train, got '4'") != std::string::npos);
}

TEST_CASE("a bad option value names the option once", "[cli][train]") {
  TempDir dir;
  const auto file = dir.Write("t.yaml", kTrain);
  const auto tier = RunCommand(kExe + " simulate " + file.string() + " --tier 9");
  CHECK(tier.exit_code == 2);
  CHECK(tier.err.find("--tier: must be 1..5") != std::string::npos);
  CHECK(tier.err.find("--tier: --tier") == std::string::npos);
  const auto axis = RunCommand(kExe + " atlas " + file.string() + " --x foo=1:2:3");
  CHECK(axis.exit_code == 2);
  CHECK(axis.err.find("--x: is not a parameter") != std::string::npos);
  CHECK(axis.err.find("--x: --x") == std::string::npos);
}

TEST_CASE("simulate and sweep: --transient and --cycles obey the file's 3600 s run-length limit",
          "[cli][train]") {
  TempDir dir;
  const auto file = dir.Write("t.yaml", kTrain);
  // meshes[0] meshes at 21 x 1000 / 60 = 350 Hz: 1e8 + 200 cycles last 2.86e5 s > 3600 s.
  const auto train = RunCommand(kExe + " simulate " + file.string() + " --transient 100000000");
  CHECK(train.exit_code == 2);
  CHECK(train.err.find("--transient: makes the 100000200 cycles of the first mesh") !=
        std::string::npos);
  CHECK(train.err.find("2.86e+05 s") != std::string::npos);
  CHECK(train.err.find("the limit is 3600 s") != std::string::npos);
  // A schema-1 pair: the same rule through the same function.
  const auto pair = RunCommand(kExe + " simulate " + std::string(GEARNVH_EXAMPLES_DIR) +
                               "/idle_rattle.yaml --transient 100000000");
  CHECK(pair.exit_code == 2);
  CHECK(pair.err.find("--transient: makes the") != std::string::npos);
}

TEST_CASE("check --json of a train names its tier (docs/results.md)", "[cli][train][json]") {
  TempDir dir;
  const auto file = dir.Write("t.yaml", Replace(kTrain, "analysis:\n", "analysis:\n  tier: 2\n"));
  const auto train = RunCommand(kExe + " check --json " + file.string());
  REQUIRE(train.exit_code == 0);
  CHECK(nlohmann::json::parse(train.out).at("tier") == "tier 2");
}

}  // namespace
}  // namespace gearnvh
