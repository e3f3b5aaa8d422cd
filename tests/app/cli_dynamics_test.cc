// End-to-end tests of `gearnvh atlas` and `gearnvh orbits` on the rattle example.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>

#include "support/run_command.h"
#include "support/paths.h"

namespace gearnvh {
namespace {

using testing::ReadWholeFile;
using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
using testing::kExamples;

// A small atlas of the idle-rattle example: low drag torque rattles chaotically, higher drag
// settles into periodic single- or double-sided rattle.
const std::string kSmallAtlas =
    " atlas --json --cycles 540 --transient 270 --x operating.speed=700rpm:1100rpm:3"
    " --y operating.torque=0.05Nm:0.5Nm:2 ";

nlohmann::json WithoutTimes(nlohmann::json doc) {
  doc.erase("wall_s");
  doc.erase("threads");
  for (auto& c : doc["cells"]) c.erase("wall_s");
  return doc;
}

TEST_CASE("atlas: 1 and 2 threads give bitwise the same cells, with regular and chaotic cells",
          "[cli][atlas]") {
  const TempDir dir;
  const auto one = RunCommand(kExe + kSmallAtlas + "--jobs 1 " + kExamples + "/idle_rattle.yaml");
  const auto two = RunCommand(kExe + kSmallAtlas + "--jobs 2 --out " + dir.path().string() + " " +
                              kExamples + "/idle_rattle.yaml");
  INFO(one.err << two.err);
  REQUIRE(one.exit_code == 0);
  REQUIRE(two.exit_code == 0);
  const auto a = nlohmann::json::parse(one.out), b = nlohmann::json::parse(two.out);
  CHECK(a["threads"] == 1);
  CHECK(b["threads"] == 2);
  // Cells are independent and deterministic: the dumps agree character for character (17
  // significant digits), which is bitwise equality of every double.
  CHECK(WithoutTimes(a).dump() == WithoutTimes(b).dump());
  REQUIRE(a["cells"].size() == 6);
  std::set<std::string> regimes;
  for (const auto& c : a["cells"]) {
    REQUIRE(c["ok"] == true);
    regimes.insert(c["regime"].get<std::string>());
    const double lambda = c["lyapunov_per_forcing_cycle"].get<double>();
    if (c["regime"] == "chaotic") {
      CHECK(lambda > 0.01);
      CHECK(c["back_impacts_per_cycle"].get<double>() > 0.0);  // chaotic rattle hits both flanks
    } else {
      CHECK(lambda < 0.0);  // a regular cell settles on an attracting orbit
    }
  }
  CHECK(regimes.count("chaotic") == 1);
  CHECK(regimes.size() >= 2);
  // Files: the same JSON and one CSV row per cell.
  const std::string csv = ReadWholeFile(dir.path() / "atlas.csv");
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 7);
  // Parameter columns in the units of the file (800 rpm, 0.2 N*m).
  CHECK(csv.rfind("ix,iy,operating.speed [rpm],operating.torque [N m],ok,lyapunov_per_s", 0) == 0);
  CHECK(WithoutTimes(nlohmann::json::parse(ReadWholeFile(dir.path() / "atlas.json"))).dump() ==
        WithoutTimes(b).dump());
}

TEST_CASE("atlas: bad axes are usage errors naming the option", "[cli][atlas]") {
  const std::string file = kExamples + "/idle_rattle.yaml";
  struct Case {
    std::string args, needle;
  };
  for (const Case& c : std::vector<Case>{
           {"--x operating.sped=1:2:3", "did you mean 'operating.speed'"},
           {"--x operating.speed=600rpm:3000rpm", "PARAMETER=FROM:TO:POINTS"},
           {"--x operating.speed=600mm:3000rpm:3", "unknown unit 'mm' for a rotational speed"},
           {"--x operating.speed=600rpm:3000rpm:0", "whole number"},
           // The rules of the file's analysis.atlas axes.
           {"--x operating.speed=600rpm:3000rpm:1", "POINTS must be >= 2"},
           {"--y operating.torque=1Nm:0.1Nm:3", "TO must be greater than from"},
           {"--x operating.torque=0.1Nm:1Nm:2", "must differ from the x parameter"},
       }) {
    INFO(c.args);
    const TempDir dir;
    const auto run = RunCommand(kExe + " atlas " + c.args + " --cycles 16 --transient 0 --out " +
                                (dir.path() / "out").string() + " " + file);
    CHECK(run.exit_code == 2);  // a usage error: the command line
    CHECK(run.err.find("error:") != std::string::npos);
    CHECK(run.err.find(c.needle) != std::string::npos);
    CHECK(!std::filesystem::exists(dir.path() / "out"));
  }
}

TEST_CASE(
    "orbits: continuation along the drag torque finds stable rattle orbits and says when "
    "none exists",
    "[cli][orbits]") {
  const TempDir dir;
  const auto run =
      RunCommand(kExe +
                 " orbits --json --transient 270 --sweep operating.torque=0.05Nm:0.5Nm:4 "
                 "--out " +
                 dir.path().string() + " " + kExamples + "/idle_rattle.yaml");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto r = nlohmann::json::parse(run.out);
  CHECK(r["period_mesh_cycles"] == 27);  // order 2 on 27 teeth
  REQUIRE(r["points"].size() == 4);
  // Chaotic rattle at the lowest drag (the atlas's chaotic cells): no stable period-1 orbit.
  const auto& low = r["points"][0];
  CHECK((low["found"] == false || low["stable"] == false));
  // High drag: a stable period-1 orbit with impacts, its multipliers inside the unit circle.
  const auto& high = r["points"][3];
  REQUIRE(high["found"] == true);
  CHECK(high["stable"] == true);
  CHECK(high["drive_impacts_per_period"].get<long>() > 0);
  for (const auto& mu : high["multipliers"]) CHECK(mu["abs"].get<double>() < 1.0);
  CHECK(high["residual"].get<double>() <= 1e-10);
  CHECK(std::filesystem::file_size(dir.path() / "orbits.csv") > 50);

  const auto text = RunCommand(kExe + " orbits --transient 270 " + kExamples +
                               "/idle_rattle.yaml --sweep operating.torque=0.05Nm:0.05Nm:1");
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("No stable period-1 orbit exists") != std::string::npos);
}

}  // namespace
}  // namespace gearnvh
