// End-to-end tests of `gearnvh simulate`.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "gearnvh/solver/trajectory.h"
#include "support/example_variant.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

using testing::kExamples;
using testing::kExe;

TEST_CASE("simulate --json: summary keys, the rattle example rattles, the loaded one does not",
          "[cli][simulate]") {
  const auto rattle = RunCommand(kExe + " simulate --json --cycles 300 --transient 100 " +
                                 kExamples + "/idle_rattle.yaml");
  INFO(rattle.err);
  REQUIRE(rattle.exit_code == 0);
  const auto r = nlohmann::json::parse(rattle.out);
  for (const char* key : {"status", "mesh_cycles", "events", "events_per_cycle", "matvec_per_cycle",
                          "wall_s", "real_time_ratio", "table_bytes"}) {
    INFO(key);
    CHECK(r["summary"].contains(key));
  }
  CHECK(r["summary"]["status"] == "success");
  // 300 recorded cycles rounded up to whole periods of the order-2 excitation (27 cycles): 324.
  CHECK(r["summary"]["mesh_cycles"] == 424);
  CHECK(r["sideband_window_cycles"] == 324);
  CHECK(r["summary"]["drive_impacts"].get<long>() > 100);  // idle rattle: impacts every cycle
  CHECK(r["summary"]["back_impacts"].get<long>() > 0);     // ... on both flanks
  CHECK(r["te_rms"].get<double>() > 1e-6);
  CHECK(r["summary"]["real_time_ratio"].get<double>() > 0.0);
  // Rattle indices: double-sided, and louder than the same gearbox without backlash.
  CHECK(r["rattle"]["regime"] == "double-sided");
  CHECK(r["rattle"]["separation_fraction"].get<double>() > 0.1);
  CHECK(r["rattle"]["no_backlash_acceleration_rms"].get<double>() > 0.0);
  CHECK(r["rattle"]["acceleration_ratio"].get<double>() > 1.5);
  // The per-second rattle a train's loose gears report: the same sums over another length (the
  // recorded cycles' time), so energy per second x seconds = energy per cycle x cycles, to the
  // rounding of two divisions (1e-12).
  const double recorded_cycles = 324.0, recorded_s = recorded_cycles * 60.0 / 800.0 / 27.0;
  CHECK(r["rattle"]["impact_energy_per_second"].get<double>() * recorded_s ==
        Approx(r["rattle"]["impact_energy_per_cycle"].get<double>() * recorded_cycles)
            .epsilon(1e-12));
  CHECK(r["rattle"]["impact_velocity_max"].get<double>() >=
        r["rattle"]["impact_velocity_rms"].get<double>());
  CHECK(r["rattle"]["back_impacts_per_second"].get<double>() > 0.0);

  const auto whine = RunCommand(kExe + " simulate --json --cycles 200 --transient 100 " +
                                kExamples + "/industrial_whine.yaml");
  REQUIRE(whine.exit_code == 0);
  const auto w = nlohmann::json::parse(whine.out);
  CHECK(w["summary"]["events"] == 0);  // permanent contact under 1.5 kN m
  CHECK(w["rattle"]["regime"] == "no impact");
  // In permanent contact the backlash only shifts the static TE: the same accelerations.
  CHECK(w["rattle"]["acceleration_ratio"].get<double>() == Approx(1.0).epsilon(1e-6));
  CHECK(w["mesh_force"]["dynamic_factor"].get<double>() > 1.0);
  CHECK(w["te"]["rms"].get<double>() < w["te"]["mean"].get<double>());
}

TEST_CASE("simulate --out writes the trajectory, events and results atomically",
          "[cli][simulate]") {
  TempDir dir;
  const auto out = dir.path() / "run";
  const auto r = RunCommand(kExe + " simulate --cycles 54 --transient 10 --out " + out.string() +
                            " " + kExamples + "/idle_rattle.yaml");
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("real time") != std::string::npos);
  CHECK(r.err.empty());  // quiet when not on a terminal
  // Units as the file wrote them (800 rpm, 0.2 N*m), µm, and what the TE mean and the dynamic
  // factor under a drag torque mean.
  INFO(r.out);
  CHECK(r.out.find("pinion at 800 rpm, 0.2 N m on the wheel") != std::string::npos);
  CHECK(r.out.find(" µm, RMS ") != std::string::npos);
  CHECK(r.out.find(" um") == std::string::npos);
  CHECK(r.out.find("the mean includes half the backlash (b = 50 µm") != std::string::npos);
  CHECK(r.out.find("dynamic factor not meaningful here") != std::string::npos);
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(out)) {
    ++files;
    CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
  }
  CHECK(files == 3);
  const std::string csv = testing::ReadWholeFile(out / "trajectory.csv");
  CHECK(csv.rfind("time_s,te_m,mesh_force_n", 0) == 0);
  // Header + 32 uniform samples per recorded cycle (54: two periods of the order-2 excitation).
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + 54 * 32);
  const auto doc = nlohmann::json::parse(testing::ReadWholeFile(out / "results.json"));
  CHECK(doc["summary"]["mesh_cycles"] == 64);
}

TEST_CASE("simulate warns up front when whole engine-order periods more than double the cycles",
          "[cli][simulate]") {
  // idle_rattle: engine order 2 on a 27-tooth pinion, so whole periods are 27 mesh cycles.
  // 10 requested -> 27 recorded (2.7x): a warning on stderr before the run, also with --json.
  const auto rounded = RunCommand(kExe + " simulate --json --cycles 10 --transient 0 " + kExamples +
                                  "/idle_rattle.yaml");
  INFO(rounded.err);
  REQUIRE(rounded.exit_code == 0);
  CHECK(rounded.err.rfind("warning: recording 27 mesh cycles, 3x the 10 requested: ", 0) == 0);
  const auto doc = nlohmann::json::parse(rounded.out);
  CHECK(doc["summary"]["mesh_cycles"].get<long>() >= 27);
  CHECK(doc["warnings"].dump().find("recording 27 mesh cycles") != std::string::npos);
  // 20 requested -> 27 (1.35x): the note in the results, no warning.
  const auto mild = RunCommand(kExe + " simulate --json --cycles 20 --transient 0 " + kExamples +
                               "/idle_rattle.yaml");
  REQUIRE(mild.exit_code == 0);
  CHECK(mild.err.find("recording") == std::string::npos);
  // The text run shows the warning once: on stderr before the run, not again among the text's
  // warning lines at the end.
  const auto text =
      RunCommand(kExe + " simulate --cycles 10 --transient 0 " + kExamples + "/idle_rattle.yaml");
  REQUIRE(text.exit_code == 0);
  const std::string shown = text.err + text.out;
  INFO(shown);
  const std::string warning = "recording 27 mesh cycles, 3x the 10 requested";
  const size_t first = shown.find(warning);
  REQUIRE(first != std::string::npos);
  CHECK(shown.find(warning, first + 1) == std::string::npos);
  CHECK(text.out.find("note: recorded 27 mesh cycles instead of 10") != std::string::npos);
}

TEST_CASE("simulate and atlas --help show what an option takes without a type-name prefix",
          "[cli][simulate]") {
  // CLI11 prints the type name and then each validator's description after a colon
  // ("--cycles INT:INT in [1, 1000000]"); the options name their range once.
  const auto help = RunCommand(kExe + " simulate --help");
  REQUIRE(help.exit_code == 0);
  INFO(help.out);
  CHECK(help.out.find("--cycles INT in [1, 1000000]") != std::string::npos);
  CHECK(help.out.find("--transient INT in [0, 100000000]") != std::string::npos);
  CHECK(help.out.find("--lyapunov INT in [1, 64]") != std::string::npos);
  CHECK(help.out.find("--tier TIER ") != std::string::npos);
  CHECK(help.out.find("--method METHOD ") != std::string::npos);
  // No type name glued to a description anywhere ("INT:INT", "TEXT:TIER", "FLOAT:NUMBER").
  for (const char* glued : {"INT:", "TEXT:", "FLOAT:"}) {
    INFO(glued);
    CHECK(help.out.find(glued) == std::string::npos);
  }
  const auto atlas = RunCommand(kExe + " atlas --help");
  REQUIRE(atlas.exit_code == 0);
  INFO(atlas.out);
  CHECK(atlas.out.find("--x PARAMETER=FROM:TO:N ") != std::string::npos);
  CHECK(atlas.out.find("--jobs INT in [1, 1024] ") != std::string::npos);
  CHECK(atlas.out.find("TEXT:") == std::string::npos);
#ifdef GEARNVH_HAVE_RENDER
  const auto tiers = RunCommand(kExe + " tiers --help");
  REQUIRE(tiers.exit_code == 0);
  INFO(tiers.out);
  CHECK(tiers.out.find("--dpi NUMBER in [36, 600]") != std::string::npos);
  CHECK(tiers.out.find("FLOAT:") == std::string::npos);
#endif
}

TEST_CASE(
    "simulate estimates its memory before the run: refused above the limit and warned near it",
    "[cli][simulate][memory]") {
  const std::string file = kExamples + "/idle_rattle.yaml";
  const std::string run = " simulate --cycles 100 --transient 0 ";
  TempDir dir;
  // The estimate, from the results of a run with room to spare; 100 cycles are rounded up to 108
  // (whole periods of the order-2 engine excitation, 27 cycles).
  const auto probe =
      RunCommand(kExe + run + "--json --out " + (dir.path() / "probe").string() + " " + file);
  REQUIRE(probe.exit_code == 0);
  const auto doc = nlohmann::json::parse(probe.out);
  const nlohmann::json& memory = doc["memory_estimate"];
  const auto estimate = memory["bytes"].get<size_t>();
  size_t sum = 0;
  for (const auto& [name, bytes] : memory["parts"].items()) sum += bytes.get<size_t>();
  CHECK(estimate == sum);
  // The recorded samples are what trajectory.csv holds (one line each after the header): counts,
  // so exactly 108 x 32 samples of sizeof(TrajectorySample).
  const std::string csv = testing::ReadWholeFile(dir.path() / "probe" / "trajectory.csv");
  const auto lines = static_cast<size_t>(std::count(csv.begin(), csv.end(), '\n'));
  CHECK(lines - 1 == 108 * 32);
  CHECK(memory["parts"]["recorded samples"].get<size_t>() ==
        (lines - 1) * sizeof(TrajectorySample));
  CHECK(memory["parts"]["backlash-free reference"] == 0);  // statistics only
  CHECK(doc["warnings"].dump().find("will hold") == std::string::npos);

  // One byte short of the estimate: refused before the run, naming the option, the value, the
  // estimate and the limit; --out is not written.
  const auto limit = [](size_t bytes) { return "GEARNVH_MEMORY_LIMIT=" + std::to_string(bytes); };
  const auto out = dir.path() / "refused";
  const auto refused =
      RunCommand(limit(estimate - 1) + " " + kExe + run + "--out " + out.string() + " " + file);
  INFO(refused.err);
  CHECK(refused.exit_code == 2);
  CHECK(refused.err.find("--cycles: the run would hold about ") != std::string::npos);
  CHECK(refused.err.find("(GEARNVH_MEMORY_LIMIT); fewer recorded cycles need less, got 100") !=
        std::string::npos);
  CHECK(refused.err.find("recorded samples 216 KiB") != std::string::npos);  // 221184 B
  CHECK(refused.out.empty());
  CHECK_FALSE(std::filesystem::exists(out));
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    INFO(e.path());
    CHECK(e.path().filename() == "probe");  // no staging folder or lock left behind
  }
  // The file's analysis.cycles: an input error at its line.
  const auto from_file = RunCommand(limit(1000) + " " + kExe + " simulate " + file);
  CHECK(from_file.exit_code == 1);
  CHECK(from_file.err.find("idle_rattle.yaml:") != std::string::npos);
  CHECK(from_file.err.find(": analysis.cycles: the run would hold about ") != std::string::npos);

  // At the limit: the run goes ahead with a warning (above half the limit), said once before the
  // run and kept in the JSON's warnings.
  const auto near = RunCommand(limit(estimate) + " " + kExe + run + "--json " + file);
  INFO(near.err);
  REQUIRE(near.exit_code == 0);
  CHECK(near.err.find("warning: --cycles 100: the run will hold about ") != std::string::npos);
  CHECK(nlohmann::json::parse(near.out)["warnings"].dump().find("the run will hold about") !=
        std::string::npos);
  const auto text = RunCommand(limit(estimate) + " " + kExe + run + file);
  const std::string shown = text.err + text.out;
  const size_t first = shown.find("the run will hold about");
  REQUIRE(first != std::string::npos);
  CHECK(shown.find("the run will hold about", first + 1) == std::string::npos);
  // With room (the estimate below half the limit): no warning.
  const auto roomy = RunCommand(limit(3 * estimate) + " " + kExe + run + file);
  CHECK(roomy.exit_code == 0);
  CHECK(roomy.err.find("will hold") == std::string::npos);
  // A malformed limit is named as the environment variable it is, not as part of the file; a
  // number past the largest size is said to be too large.
  const auto bad = RunCommand("GEARNVH_MEMORY_LIMIT=1GB " + kExe + run + file);
  CHECK(bad.exit_code == 1);
  CHECK(bad.err ==
        "error: the environment variable GEARNVH_MEMORY_LIMIT is '1GB': it must be a whole number "
        "of bytes\n");
  const auto huge = RunCommand("GEARNVH_MEMORY_LIMIT=99999999999999999999999 " + kExe + run + file);
  CHECK(huge.exit_code == 1);
  CHECK(huge.err ==
        "error: the environment variable GEARNVH_MEMORY_LIMIT is 99999999999999999999999: too "
        "large, at most 18446744073709551615 bytes\n");
}

TEST_CASE("a malformed GEARNVH_MEMORY_LIMIT is an input error in every command that reads it",
          "[cli][memory]") {
  // report read it outside the commands' error mapping: an internal error (exit 3) until
  // 2026-12-01. Every command checks the limit before its run, so each fails at once.
  const TempDir dir;
  const std::string pair = kExamples + "/idle_rattle.yaml";
  const std::string train = kExamples + "/two_stage_helical_reducer.yaml";
  const std::string commands[] = {
      " simulate --cycles 10 " + pair,
      " simulate --cycles 10 " + train,
      " sweep --cycles 10 " + pair,
      " tiers --cycles 10 " + pair,
      " report " + pair + " --out " + (dir.path() / "report").string(),
  };
  for (const std::string& command : commands) {
    const auto r = RunCommand("GEARNVH_MEMORY_LIMIT=1GB " + kExe + command);
    INFO(command << "\n" << r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find("error: the environment variable GEARNVH_MEMORY_LIMIT is '1GB': it must be a "
                     "whole number of bytes\n") != std::string::npos);
    CHECK(r.err.find("internal error") == std::string::npos);
  }
  CHECK_FALSE(std::filesystem::exists(dir.path() / "report"));
}

TEST_CASE("simulate: bad options and unavailable tiers are clear errors", "[cli][simulate]") {
  const auto bad_tier = RunCommand(kExe + " simulate --tier 9 " + kExamples + "/idle_rattle.yaml");
  CHECK(bad_tier.exit_code == 2);  // a usage error
  CHECK(bad_tier.err.find("--tier") != std::string::npos);
  const auto no_shafts = RunCommand(kExe + " simulate --tier 5 " + kExamples + "/idle_rattle.yaml");
  CHECK(no_shafts.exit_code == 2);  // the flag chose the tier: a usage error naming it
  CHECK(no_shafts.err.find("--tier: needs flexible shafts") != std::string::npos);
  CHECK(no_shafts.err.find("got 5") != std::string::npos);
  CHECK(no_shafts.err.find("idle_rattle.yaml") != std::string::npos);
  CHECK(RunCommand(kExe + " simulate --cycles 0 " + kExamples + "/idle_rattle.yaml").exit_code ==
        2);
  CHECK(RunCommand(kExe + " simulate").exit_code == 2);
  const auto help = RunCommand(kExe + " simulate --help");
  CHECK(help.exit_code == 0);
  CHECK(help.out.find("--tier") != std::string::npos);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("validate passes on every bundled example and --json lists the checks",
          "[cli][validate]") {
  for (const char* example :
       {"idle_rattle.yaml", "industrial_whine.yaml", "flexible_shafts.yaml"}) {
    const auto r = testing::RunCommand(std::string(GEARNVH_EXE) + " validate --json " +
                                       GEARNVH_EXAMPLES_DIR + "/" + example);
    INFO(example << "\n" << r.out << r.err);
    CHECK(r.exit_code == 0);
    const auto doc = nlohmann::json::parse(r.out);
    REQUIRE(doc["checks"].size() >= 8);
    int run = 0;
    for (const auto& c : doc["checks"]) {
      CHECK(c.contains("name"));
      CHECK(c.contains("value"));
      CHECK(c.contains("threshold"));
      CHECK(c["pass"].get<bool>());
      run += c["skipped"].get<bool>() ? 0 : 1;
    }
    CHECK(run >= 5);  // most rows really ran
  }
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("simulate --out into an unwritable place is a clear I/O error with exit 4",
          "[cli][simulate]") {
  testing::TempDir dir;
  const auto blocker = dir.Write("not_a_dir", "x");  // a file where the output directory should go
  const auto r = testing::RunCommand(
      std::string(GEARNVH_EXE) + " simulate --cycles 5 --transient 0 --out " +
      (blocker / "run").string() + " " + GEARNVH_EXAMPLES_DIR + "/idle_rattle.yaml");
  CHECK(r.exit_code == 4);
  CHECK(r.err.find("error:") != std::string::npos);
  CHECK(r.err.find("internal error") == std::string::npos);
}

TEST_CASE("simulate: a response growing without bound ends out_of_range with exit 1",
          "[cli][simulate]") {
  // examples/flexible_shafts.yaml at the preprint's strong-rattle point, tier 2: the lateral modes
  // are barely damped and one flank at a time carries load, so the rattle grows (docs/solver.md,
  // "One flank at a time, and the range check"); the run stops at the range check.
  TempDir dir;
  const std::string file = testing::WriteExampleVariant(
                               dir, "flexible_shafts.yaml",
                               {{"  speed: 3000 rpm\n  torque: 200 N*m\n",
                                 "  speed: 7548.387097 rpm\n  torque: 20 N*m\n  excitation:\n"
                                 "    - {order: 15.5, amplitude: 200000 rad/s^2, phase: 0 deg}\n"}})
                               .string();
  const auto run =
      RunCommand(kExe + " simulate --json --tier 2 --cycles 500 --transient 100 " + file);
  INFO(run.err);
  CHECK(run.exit_code == 1);
  const auto r = nlohmann::json::parse(run.out);
  CHECK(r["summary"]["status"] == "out_of_range");
  CHECK(r["summary"]["mesh_cycles"].get<long>() < 600);
  CHECK(r["summary"]["message"].get<std::string>().find("past the teeth's whole depth") !=
        std::string::npos);
  // Every TE number written is a finite number within twice the limit (6.87 mm): the run stopped
  // at the first cycle end past it, long before the growth overflowed.
  for (const auto& [key, value] : r["te"].items()) {
    if (key.find("note") != std::string::npos) continue;
    INFO(key);
    REQUIRE(value.is_number());
    CHECK(std::abs(value.get<double>()) < 2.0 * 6.87e-3);
  }
}

}  // namespace
}  // namespace gearnvh
