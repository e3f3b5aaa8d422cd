// End-to-end tests of `gearnvh sweep` and the sidebands of `gearnvh simulate`.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/example_variant.h"
#include "support/paths.h"
#include "support/run_command.h"
#include "support/sanitizer.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
using testing::kExamples;

TEST_CASE("simulate --json lists only the mesh harmonics when nothing can make sidebands",
          "[cli][sidebands]") {
  // industrial_whine has no runout, pitch error or engine order: every recorded cycle is in the
  // spectrum, only mesh harmonics are listed, and a note says why.
  const auto run = RunCommand(kExe + " simulate --json --cycles 160 --transient 50 " + kExamples +
                              "/industrial_whine.yaml");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto r = nlohmann::json::parse(run.out);
  CHECK(r["sideband_window_cycles"] == 160);
  REQUIRE(r["sidebands"].size() == 3);
  CHECK(r["sidebands"][0]["label"] == "1 fm");
  CHECK(r["sidebands"][0]["amplitude_m"].get<double>() > 1e-7);  // loaded whine: micrometres
  bool explained = false;
  for (const auto& note : r["sidebands_notes"]) {
    explained |=
        note.get<std::string>().find("no runout, pitch error or engine order") != std::string::npos;
  }
  CHECK(explained);
}

TEST_CASE("simulate with pinion runout: the 1x pinion line equals the runout at low speed",
          "[cli][sidebands][runout]") {
  // 60 rpm loaded: quasi-static, so delta = b + e + F/k and the line at f1 is the runout
  // amplitude; the segment mean of a sinusoid attenuates it by (pi / (z1 S))^2 / 6 = 3e-6 here.
  const TempDir dir;
  const std::string relief = "    tip_relief: {amount: 20 um, length: 8 mm}\n";
  const auto file = dir.Write(
      "runout.yaml",
      testing::ExampleVariantText(
          "industrial_whine.yaml",
          {{"speed: 1500 rpm", "speed: 60 rpm"},
           {relief, relief + "    runout: {amplitude: 10 um, phase: 30 deg}\n"}}));
  const auto run =
      RunCommand(kExe + " simulate --json --cycles 110 --transient 50 " + file.string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto r = nlohmann::json::parse(run.out);
  // 110 cycles are rounded up to whole revolutions of the pinion, which carries the error: 125.
  CHECK(r["sideband_window_cycles"] == 125);
  double pinion_line = 0.0;
  bool sideband = false;
  for (const auto& row : r["sidebands"]) {
    const std::string label = row["label"].get<std::string>();
    if (label.rfind("1 f1", 0) == 0) pinion_line = row["amplitude_m"].get<double>();
    sideband |= label.rfind("1 fm + 1 f1", 0) == 0;
  }
  CHECK(pinion_line == Approx(10e-6).epsilon(1e-5));
  CHECK(sideband);  // runout modulates the mesh: fm +- f1 appear
}

TEST_CASE("sweep writes Campbell and waterfall data atomically and reports per speed",
          "[cli][sweep]") {
  const TempDir dir;
#if defined(GEARNVH_UNDER_ASAN)
  // 12 of the file's 35 speeds over the same range (35 took 81 s CPU under the sanitizers).
  const std::string file = testing::WriteExampleVariant(dir, "flexible_shafts.yaml",
                                                        {{"points: 35}", "points: 12}"}})
                               .string();
  const size_t expected_speeds = 12;
#else
  const std::string file = kExamples + "/flexible_shafts.yaml";
  const size_t expected_speeds = 35;
#endif
  const std::filesystem::path out = dir.path() / "sweep";
  const auto run = RunCommand(kExe + " sweep --json --cycles 64 --transient 20 --jobs 2 --out " +
                              out.string() + " " + file);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto r = nlohmann::json::parse(run.out);
  const size_t speeds = r["speeds_rpm"].size();
  CHECK(speeds == expected_speeds);
  CHECK(r["failed_speeds"] == 0);
  CHECK(r["waterfall"]["amplitude_m"].size() == speeds);
  // Every mode below 3x the highest mesh frequency (31 teeth at 6000 rpm: 9.3 kHz) of N20 MTA.
  CHECK(r["campbell"]["modes"].size() >= 8);
  for (const auto& mode : r["campbell"]["modes"]) {
    CHECK(mode.contains("label"));
    CHECK(mode["damping_ratio"].size() == speeds);
  }
  CHECK(r["campbell"]["orders"].size() == 7);
  CHECK(!r["campbell"]["critical_speeds"].empty());
  for (const char* file : {"campbell.csv", "critical_speeds.csv", "waterfall.csv", "sweep.json"}) {
    INFO(file);
    CHECK(std::filesystem::file_size(out / file) > 30);
  }
  // No temporary files left behind.
  for (const auto& entry : std::filesystem::directory_iterator(out)) {
    CHECK(entry.path().filename().string().find(".tmp") == std::string::npos);
  }
  // Loaded example: the waterfall's largest line at every speed is a mesh harmonic (which one
  // depends on the resonances the harmonics cross).
  const double step = r["waterfall"]["order_step"].get<double>();
  const double mesh_order = r["waterfall"]["mesh_order"].get<double>();
  for (const auto& row : r["waterfall"]["amplitude_m"]) {
    size_t best = 1;
    for (size_t k = 1; k < row.size(); ++k)
      if (row[k].get<double>() > row[best].get<double>()) best = k;
    const double harmonic = std::round(best * step / mesh_order);
    CHECK(harmonic >= 1.0);
    CHECK(harmonic <= 3.0);
    CHECK(std::abs(best * step - harmonic * mesh_order) <= step);
  }
}

TEST_CASE("sweep text shows the speeds in the unit the file wrote, the JSON in rpm",
          "[cli][sweep]") {
  // The idle-rattle example with its speeds in rev/s (10, 30, 50 rev/s = 600, 1800, 3000 rpm).
  const TempDir dir;
  const auto file = dir.Write(
      "revs.yaml",
      testing::ExampleVariantText(
          "idle_rattle.yaml",
          {{"speed_sweep: {from: 600 rpm, to: 3000 rpm, points: 25}",
            "speed_sweep: {from: 10 rev/s, to: 50 rev/s, points: 3}"},
           {"speed: 800 rpm", "speed: 13.5 rev/s"}}));
  const std::string command = kExe + " sweep --cycles 16 --transient 4 " + file.string();
  const auto run = RunCommand(command);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.out.find("     rev/s   TE RMS µm") != std::string::npos);
  for (const char* row : {"\n        10  ", "\n        30  ", "\n        50  "}) {
    CHECK(run.out.find(row) != std::string::npos);
  }
  CHECK(run.out.find("rpm") == std::string::npos);
  const auto json = RunCommand(command + " --json");
  REQUIRE(json.exit_code == 0);
  const auto speeds = nlohmann::json::parse(json.out)["speeds_rpm"];
  REQUIRE(speeds.size() == 3);
  CHECK(speeds[2].get<double>() == Approx(3000.0).epsilon(1e-12));  // 50 rev/s, rounding only
}

TEST_CASE("sweep: too few cycles is a usage error, a bad file a clear input error",
          "[cli][sweep]") {
  const auto run = RunCommand(kExe + " sweep --cycles 1 " + kExamples + "/idle_rattle.yaml");
  CHECK(run.exit_code == 2);  // --cycles must be >= 2 (usage)
  const TempDir dir;
  const auto bad_file = dir.path() / "bad.yaml";
  std::ofstream(bad_file) << "name: no materials\n";
  const TempDir out;
  const auto bad = RunCommand(kExe + " sweep --out " + (out.path() / "sweep").string() + " " +
                              bad_file.string());
  CHECK(bad.exit_code == 1);
  CHECK(bad.err.find("materials") != std::string::npos);
  CHECK(bad.err.find("bad.yaml") != std::string::npos);
  CHECK(!std::filesystem::exists(out.path() / "sweep"));  // nothing written
}

TEST_CASE("sweep refuses a sweep whose speeds in flight would hold more than the memory limit",
          "[cli][sweep][memory]") {
  // Each speed in flight keeps its recording: 100 cycles x 32 samples x sizeof(TrajectorySample)
  // (64 B) = 200 KiB, twice with two speeds at once.
  TempDir out;
  const std::string sweep = " sweep --cycles 100 --transient 0 --out " +
                            (out.path() / "sweep").string() + " " + kExamples + "/idle_rattle.yaml";
  const auto one = RunCommand("GEARNVH_MEMORY_LIMIT=1 " + kExe + sweep + " --jobs 1");
  INFO(one.err);
  CHECK(one.exit_code == 2);
  CHECK(one.err.find("--cycles: the run would hold about ") != std::string::npos);
  CHECK(one.err.find("recorded samples 200 KiB") != std::string::npos);
  CHECK(one.err.find("fewer recorded cycles or --jobs need less, got 100") != std::string::npos);
  const auto two = RunCommand("GEARNVH_MEMORY_LIMIT=1 " + kExe + sweep + " --jobs 2");
  INFO(two.err);
  CHECK(two.exit_code == 2);
  CHECK(two.err.find("recorded samples 400 KiB") != std::string::npos);
  CHECK(!std::filesystem::exists(out.path() / "sweep"));  // nothing written
  // Without --cycles the cycles are sweep's default, not a usage error: exit 1, saying so.
  const auto by_default =
      RunCommand("GEARNVH_MEMORY_LIMIT=1 " + kExe + " sweep --jobs 1 --out " +
                 (out.path() / "sweep").string() + " " + kExamples + "/idle_rattle.yaml");
  INFO(by_default.err);
  CHECK(by_default.exit_code == 1);
  CHECK(by_default.err.find("the default cycles per speed (set by --cycles): the run would hold "
                            "about ") != std::string::npos);
  CHECK(by_default.err.find("got 512") != std::string::npos);
  CHECK(!std::filesystem::exists(out.path() / "sweep"));
}

TEST_CASE("sweep and atlas: a failed speed or cell has null results, not 0", "[cli][sweep]") {
  const TempDir dir;
  const std::string file =
      testing::WriteExampleVariant(dir, "flexible_shafts.yaml",
                                   {testing::kStrongRattlePoint, testing::kStrongRattleSweep})
          .string();
  const auto sweep =
      RunCommand(kExe + " sweep --json --tier 2 --cycles 300 --transient 100 " + file);
  INFO(sweep.err);
  CHECK(sweep.exit_code == 1);
  const auto doc = nlohmann::json::parse(sweep.out);
  CHECK(doc["failed_speeds"] == 1);
  const auto& points = doc["waterfall"]["points"];
  REQUIRE(points.size() == 3);
  CHECK_FALSE(points[2]["ok"].get<bool>());
  for (const char* key : {"te_rms", "te_peak_to_peak", "events_per_cycle",
                          "drive_impacts_per_cycle", "back_impacts_per_cycle"}) {
    INFO(key);
    CHECK(points[2][key].is_null());
    CHECK(points[0][key].get<double>() > 0.0);
  }

  const auto atlas = RunCommand(kExe + " atlas --json --tier 2 --cycles 300 --transient 100 " +
                                "--x operating.speed=5000rpm:6000rpm:3 " +
                                "--y operating.torque=20Nm:21Nm:2 --out " +
                                (dir.path() / "atlas").string() + " " + file);
  INFO(atlas.err);
  CHECK(atlas.exit_code == 1);
  int failed = 0;
  const auto cells = nlohmann::json::parse(atlas.out)["cells"];
  for (const auto& c : cells) {
    if (c["ok"].get<bool>()) {
      CHECK(c["rattle_index_j"].get<double>() > 0.0);
      continue;
    }
    ++failed;
    for (const char* key :
         {"lyapunov_per_s", "rattle_index_j", "separation_fraction", "drive_impacts_per_cycle"}) {
      INFO(key);
      CHECK(c[key].is_null());
    }
  }
  CHECK(failed == 2);  // the 6000 rpm column
  // atlas.csv: a failed cell's results are empty fields (,0,,,,,,,,,,message), not 0.
  const std::string csv = testing::ReadWholeFile(dir.path() / "atlas" / "atlas.csv");
  CHECK(csv.find(",0,,,,,,,,,,") != std::string::npos);
  CHECK(csv.find("nan") == std::string::npos);
}

}  // namespace
}  // namespace gearnvh
