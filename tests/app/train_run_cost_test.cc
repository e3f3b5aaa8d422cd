// The slow-run estimate (analysis/include/gearnvh/analysis/run_cost.h, EstimateRunCost) against the
// solver: its sub-step is 1 / (2 rho) with the table cache's own bound rho of the same tuple
// (TrainSystem::rho, both from BoundTupleRate), and a run on the dense path takes the sub-steps
// those bounds allow; the refusal above an hour (--allow-slow) and the warning above a minute.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "app/loose_gear_train_yaml.h"
#include "app/three_shaft_train_yaml.h"
#include "config/gearbox_loader.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "gearnvh/solver/train_stepper.h"
#include "gearnvh/solver/train_tables.h"
#include "model/test_trains.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::kExamples;
using testing::kExe;
using testing::RunCommand;

TrainSpec LinearTrain() {
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(
      testing::ReadWholeFile(std::filesystem::path(GEARNVH_TEST_DATA_DIR) / "linear_train.yaml"));
  REQUIRE(loaded.schema == 2);
  return loaded.train;
}

// The rattler's loose gear g4 at 1e-9 kg m^2 (the slow-run warning's case), without excitation.
TrainSpec TinyLooseGear() {
  TrainSpec spec = testing::RattlerTrain(0.0);
  spec.gears[3].gear.inertia = 1e-9;
  return spec;
}

// Every tuple of every mesh in drive contact (the product of the meshes' segments).
void ForEachDriveTuple(const TrainTables& t, const std::vector<int>& prefix,
                       const std::function<void(const std::vector<int>&)>& visit) {
  if (prefix.size() == t.meshes.size()) return visit(prefix);
  for (int j = 0; j < t.meshes[prefix.size()].segments(); ++j) {
    std::vector<int> next = prefix;
    next.push_back(j);
    ForEachDriveTuple(t, next, visit);
  }
}

// The estimate equals the solver's bound of the tuple at t = 0 exactly (one function, the same
// inputs: no tolerance), and a run that never decomposes (every piece on the dense path), stays
// in drive contact (no event) and neither jumps nor fuses takes N sub-steps with
//   T / max_s substep_s <= N <= T / min_s substep_s + G,
// s over the drive tuples, G the grid segments (each may end with one short sub-step; piece
// boundaries inside a grid segment only come from events, none here).
void CheckAgainstRun(const TrainSpec& spec, double seconds) {
  const TrainTables t = BuildTrainTables(spec, BuildGearTrain(spec));
  const gearnvh::RunCostEstimate cost = gearnvh::EstimateRunCost(t);
  TrainStepperOptions options;
  options.tables.decompose_after_visits = std::numeric_limits<int>::max();
  options.jumps = false;
  options.fusion_levels = 0;
  TrainSystemCache cache(t, options.tables);
  TupleKey key(static_cast<size_t>(cache.KeyWords()));
  const std::vector<ContactState> drive(t.meshes.size(), ContactState::kDrive);
  const TrainSystem& start = cache.Get(std::vector<int>(t.meshes.size(), 0), drive, key);
  REQUIRE(start.rho > 0.0);
  CHECK(cost.substep_s == 0.5 / start.rho);
  double shortest = std::numeric_limits<double>::infinity(), longest = 0.0;
  ForEachDriveTuple(t, {}, [&](const std::vector<int>& segments) {
    const double s = cache.Get(segments, drive, key).substep;
    shortest = std::min(shortest, s);
    longest = std::max(longest, s);
  });

  const auto [z0, states0] = TrainStaticState(t);
  REQUIRE(states0 == drive);
  TrainStepper stepper(t, options, z0, states0);
  REQUIRE(stepper.Run(seconds));
  const TrainStepperSummary& s = stepper.summary();
  REQUIRE(s.events == 0);
  const double n = static_cast<double>(s.dense_pieces);
  INFO("sub-steps " << n << ", estimate " << seconds / cost.substep_s << ", shortest " << shortest
                    << " s, longest " << longest << " s, estimate's " << cost.substep_s
                    << " s, grid segments " << s.grid_segments);
  CHECK(n >= seconds / longest * (1.0 - 1e-12));
  CHECK(n <= seconds / shortest + static_cast<double>(s.grid_segments));
  // The estimate's tuple is one of them, and its sub-step is never shorter than the solver's
  // there (the solver also bounds the balanced row norm).
  CHECK(start.substep <= cost.substep_s);
  CHECK(start.substep >= shortest);
  CHECK(start.substep <= longest);
}

TEST_CASE("the slow-run estimate is the solver's bound and counts a dense run's sub-steps",
          "[train][warnings]") {
  // The linear train's grid segments (31 us) are shorter than its sub-step (50 us): one sub-step
  // each (measured 640 = G against T / s = 396), so there the count only brackets. The tiny loose
  // gear's sub-steps (44-58 ns) are far shorter than its grid segments: measured 45,220 against
  // the estimate's 42,336 (+7 %, its segment 0 being softer than the mean).
  SECTION("linear train (tests/data)") { CheckAgainstRun(LinearTrain(), 0.02); }
  SECTION("tiny loose gear") { CheckAgainstRun(TinyLooseGear(), 2e-3); }
}

// The loose-gear train (loose_gear_train_yaml.h) with its loose gear f at `inertia`.
std::string TinyLooseGearYaml(const std::string& inertia) {
  return testing::ReplaceFirst(testing::kLooseGearTrainYaml,
                               "bore_diameter: 30 mm, material: steel}",
                               "bore_diameter: 30 mm, material: steel, inertia: " + inertia + "}");
}

TEST_CASE("simulate refuses a run estimated above an hour and names --allow-slow and the body",
          "[cli][train][warnings]") {
  // f at 1e-15 kg m^2: its mode sqrt(k r_b^2 / J) is ~1e10 rad/s, so the default run (2500
  // cycles of a-b, ~7 s simulated) needs ~1e11 sub-steps: hours even at a third of the measured
  // cost per sub-step. Refused before anything runs, exit 2 (a usage error: the option allows it).
  const testing::TempDir dir;
  const std::string file = dir.Write("tiny.yaml", TinyLooseGearYaml("1e-15 kg*m^2")).string();
  // At tier 1 and at a reduced tier (whose coordinates are modal: the body's own inertia is named,
  // not a modal mass).
  for (const std::string tier : {"1", "2"}) {
    INFO("tier " << tier);
    const auto r = RunCommand(kExe + " simulate --tier " + tier + " " + file);
    INFO(r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.out.empty());
    CHECK(r.err.find("error: ") != std::string::npos);
    CHECK(r.err.find("--allow-slow") != std::string::npos);
    CHECK(r.err.find("the run would take about") != std::string::npos);
    CHECK(r.err.find("body f, inertia 1e-15 kg m²") != std::string::npos);
    CHECK(r.err.find("dominated by stiffness") != std::string::npos);
  }
}

TEST_CASE("validate refuses a ladder estimated above an hour and names --allow-slow",
          "[cli][train][warnings]") {
  // The same train: the ladder's exact runs of up to 200 cycles each (~0.5 s simulated in all)
  // need ~1e10 sub-steps. Refused before any run, exit 2, nothing on stdout.
  const testing::TempDir dir;
  const std::string file = dir.Write("tiny.yaml", TinyLooseGearYaml("1e-15 kg*m^2")).string();
  const auto r = RunCommand(kExe + " validate " + file);
  INFO(r.err);
  CHECK(r.exit_code == 2);
  CHECK(r.out.empty());
  CHECK(r.err.find("--allow-slow") != std::string::npos);
  CHECK(r.err.find("the validation's exact runs (each up to 200 cycles of mesh a-b") !=
        std::string::npos);
  CHECK(r.err.find("body f, inertia 1e-15 kg m²") != std::string::npos);
}

TEST_CASE("simulate --allow-slow starts the run it would refuse, saying its cost first",
          "[cli][train][warnings]") {
  // The refused run above with --allow-slow: not refused, the warning is on stderr before the run,
  // and the run is still going after 5 s of CPU time (its start, refused or not, takes ~0.5 s),
  // when the CPU limit kills it (SIGXCPU or SIGKILL at the hard limit: 152 or 137). A CPU limit,
  // not a wall-clock one: on a loaded machine the start alone took 13 s of wall time. A single
  // cycle of it would also take minutes (~9e7 sub-steps), so the run is not waited for.
  const testing::TempDir dir;
  const std::string file = dir.Write("tiny.yaml", TinyLooseGearYaml("1e-15 kg*m^2")).string();
  const auto r = RunCommand("ulimit -t 5; exec " + kExe + " simulate --allow-slow " + file);
  INFO(r.err);
  CHECK((r.exit_code == 152 || r.exit_code == 137));
  CHECK(r.err.find("warning: the run would take about") != std::string::npos);
  CHECK(r.err.find("error:") == std::string::npos);
}

TEST_CASE("an ordinary train is neither refused nor warned about its cost",
          "[cli][train][warnings]") {
  // Every bundled train's run as its file sets it (analysis tier, cycles and transient) is
  // estimated below the warning's minute, and the light loose gear of the loose-gear train
  // (f as written, ~1e-4 kg m^2) runs without a word about its cost.
  for (const char* name : {"manual_transmission_idle.yaml", "two_stage_helical_reducer.yaml"}) {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(
        testing::ReadWholeFile(std::filesystem::path(kExamples) / name));
    REQUIRE(loaded.schema == 2);
    const TrainSpec& spec = loaded.train;
    const TrainTables t = BuildTrainTablesAtTier(spec, BuildGearTrain(spec), spec.analysis.tier);
    const double seconds =
        static_cast<double>(spec.analysis.cycles + spec.analysis.transient_cycles) *
        t.meshes.front().period;
    const gearnvh::RunCostEstimate cost = gearnvh::EstimateRunCost(t, seconds, &spec);
    INFO(name << ": " << gearnvh::RunCostText(cost, "the run"));
    CHECK(cost.wall_s < gearnvh::kSlowRunWarnSeconds);
    CHECK(gearnvh::CheckRunCost(cost, false).empty());
  }
  const testing::TempDir dir;
  const std::string file = dir.Write("loose.yaml", testing::kLooseGearTrainYaml).string();
  const auto r = RunCommand(kExe + " simulate --cycles 200 --transient 50 " + file);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.err.find("would take about") == std::string::npos);
  CHECK(r.err.find("--allow-slow") == std::string::npos);
}

TEST_CASE("the run-cost check refuses above an hour only without allow_slow", "[train][warnings]") {
  // The refusal and the warning follow the estimate's wall time alone: 59 s nothing, 61 s a
  // warning, 3601 s a refusal naming the option as the caller spells it ("--allow-slow" on the
  // command line, "allow_slow" for the Python keyword), unless allowed.
  gearnvh::RunCostEstimate cost;
  cost.substep_s = 1e-9;
  cost.cause_body_name = "g";
  cost.wall_s = 59.0;
  CHECK(gearnvh::CheckRunCost(cost, false).empty());
  cost.wall_s = 61.0;
  CHECK(!gearnvh::CheckRunCost(cost, false).empty());
  cost.wall_s = 3601.0;
  CHECK(!gearnvh::CheckRunCost(cost, true).empty());
  try {
    (void)gearnvh::CheckRunCost(cost, false);
    FAIL("not refused");
  } catch (const InputError& e) {
    CHECK(e.path() == "--allow-slow");
  }
  try {
    (void)gearnvh::CheckRunCost(cost, false, "the run", gearnvh::OptionNames{""});
    FAIL("not refused");
  } catch (const InputError& e) {
    CHECK(e.path() == "allow_slow");
  }
}

}  // namespace
}  // namespace gearnvh
