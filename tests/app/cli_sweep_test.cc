// End-to-end tests of `gearnvh sweep` and the sidebands of `gearnvh simulate`.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

const std::string kExe = GEARNVH_EXE;
const std::string kExamples = GEARNVH_EXAMPLES_DIR;

TEST_CASE("simulate --json lists mesh harmonics and sidebands over whole shaft revolutions",
          "[cli][sidebands]") {
  // industrial_whine: 25:75, lcm 75 cycles; 160 recorded cycles -> a 150-cycle window.
  const auto run = RunCommand(kExe + " simulate --json --cycles 160 --transient 50 " + kExamples +
                              "/industrial_whine.yaml");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto r = nlohmann::json::parse(run.out);
  CHECK(r["sideband_window_cycles"] == 150);
  REQUIRE(r["sidebands"].size() == 3 * (1 + 4 * 3));  // 3 harmonics, +-1..3 of both shafts
  const auto& first = r["sidebands"][0];
  CHECK(first["label"] == "1 fm");
  // Loaded whine: the TE at mesh frequency is the dominant line (a micrometre scale), and with no
  // runout or eccentricity in the model the shaft-order sidebands sit at rounding level.
  CHECK(first["amplitude_m"].get<double>() > 1e-7);
  for (const auto& row : r["sidebands"]) {
    const std::string label = row["label"].get<std::string>();
    if (label.find(" f1") != std::string::npos || label.find(" f2") != std::string::npos) {
      CHECK(row["amplitude_m"].get<double>() < 1e-6 * first["amplitude_m"].get<double>());
    }
  }
}

TEST_CASE("sweep writes Campbell and waterfall data atomically and reports per speed",
          "[cli][sweep]") {
  const TempDir dir;
  const auto run = RunCommand(kExe + " sweep --json --cycles 64 --transient 20 --jobs 2 --out " +
                              dir.path().string() + " " + kExamples + "/flexible_shafts.yaml");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto r = nlohmann::json::parse(run.out);
  const size_t speeds = r["speeds_rpm"].size();
  CHECK(speeds == 35);
  CHECK(r["failed_speeds"] == 0);
  CHECK(r["waterfall"]["amplitude_m"].size() == speeds);
  CHECK(r["campbell"]["modes"].size() == 8);
  CHECK(r["campbell"]["orders"].size() == 7);
  CHECK(!r["campbell"]["critical_speeds"].empty());
  for (const char* file : {"campbell.csv", "critical_speeds.csv", "waterfall.csv", "sweep.json"}) {
    INFO(file);
    CHECK(std::filesystem::file_size(dir.path() / file) > 30);
  }
  // No temporary files left behind.
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
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

}  // namespace
}  // namespace gearnvh
