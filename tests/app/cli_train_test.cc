// End-to-end tests of gear trains (schema gearnvh/2) through `gearnvh check`.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>

#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;
namespace fs = std::filesystem;

using testing::kExamples;
using testing::kExe;

TEST_CASE("check lists each load's drag and the power it takes, which the input supplies",
          "[cli][train]") {
  // The manual transmission at idle with o2's drag on its speed relative to the output shaft it
  // idles on (a needle bearing: T + c |dW|) and churning on the layshaft (absolute). Every load's
  // power (T + c |dW|) |dW| sums to what the input torque supplies at the input speed (power
  // balance, the static torque flow's rule: 1e-9 relative), and o2's mean torque is T + c |dW|.
  std::ifstream in(kExamples + "/manual_transmission_idle.yaml");
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("{on: o2, torque: 0.2 N*m}",
          "{on: o2, torque: 0.1 N*m, viscous: 1 N*mm*s/rad, relative_to: output}");
  replace("{on: layshaft, torque: 0.4 N*m}", "{on: layshaft, torque: 0.2 N*m, viscous: 2e-3}");
  const TempDir dir;
  const auto file = dir.Write("drag.yaml", text);
  const auto r = RunCommand(kExe + " check --json " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc["loads"].size() == 6);
  double power = 0.0;
  for (const auto& l : doc["loads"]) power += l["power_w"].get<double>();
  double input_speed = 0.0;
  for (const auto& b : doc["bodies"])
    if (b["name"] == "input") input_speed = b["speed"].get<double>();
  CHECK(power == Approx(doc["input_torque"].get<double>() * input_speed).epsilon(1e-9));
  const auto& o2 = doc["loads"][2];
  CHECK(o2["on"] == "o2");
  CHECK(o2["relative_to"] == "output");
  const double dw = o2["relative_speed_rpm"].get<double>() * std::numbers::pi / 30.0;
  CHECK(o2["mean_torque_n_m"].get<double>() == Approx(0.1 + 1e-3 * std::abs(dw)).epsilon(1e-12));
  CHECK(doc["loads"][1]["relative_to"].is_null());
  // The text gives the drag in the units written.
  const auto t = RunCommand(kExe + " check " + file.string());
  CHECK(t.out.find("1 N mm s/rad") != std::string::npos);
  CHECK(t.out.find("relative to") != std::string::npos);
}

TEST_CASE("check on the manual transmission reports every mesh and body", "[cli][train]") {
  const auto r = RunCommand(kExe + " check --json " + kExamples + "/manual_transmission_idle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc["meshes"].size() == 6);
  CHECK(doc["meshes"][0]["name"] == "in-l0");
  const auto& g = doc["meshes"][2]["geometry"];
  // Helical: eps_beta = b sin(beta) / (pi m_n) with b = 17 mm, beta = 25 deg, m_n = 2.25 mm.
  const double beta = 25.0 * std::numbers::pi / 180.0;
  CHECK(g["overlap_ratio"].get<double>() ==
        Approx(17.0 * std::sin(beta) / (std::numbers::pi * 2.25)).epsilon(1e-12));
  CHECK(g["total_contact_ratio"].get<double>() ==
        Approx(g["contact_ratio"].get<double>() + g["overlap_ratio"].get<double>()).epsilon(1e-12));
  for (const auto& m : doc["meshes"]) {
    CHECK(m["stiffness"]["mean"].get<double>() > 1e8);  // N/m: a steel pair of this size
    CHECK(m["stiffness"]["min"].get<double>() <= m["stiffness"]["mean"].get<double>());
  }
  // Bodies: 3 shafts and 4 loose gears; the loose 2nd gear turns at 800 (21/35)(24/32) rpm, the
  // way the input does (two reversals).
  REQUIRE(doc["bodies"].size() == 7);
  CHECK(doc["bodies"][3]["name"] == "o2");
  CHECK(doc["bodies"][3]["kind"] == "loose gear");
  CHECK(doc["bodies"][3]["speed_rpm"].get<double>() ==
        Approx(800.0 * 21.0 / 35.0 * 24.0 / 32.0).epsilon(1e-12));
  CHECK(doc["tiers"][0]["free_rotations"] == 1);
  CHECK(doc["tiers"][0]["natural_frequencies_hz"].size() == 6);
  CHECK_FALSE(doc["critical_speeds"].empty());
}

TEST_CASE("check reports a train's FE model, tiers and Campbell data", "[cli][train]") {
  const auto r =
      RunCommand(kExe + " check --json " + kExamples + "/two_stage_helical_reducer.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["fe"]["free_rotations"] == 1);
  CHECK(doc["fe"]["rigid_body_modes"] == 1);
  REQUIRE(doc["fe"]["natural_frequencies_hz"].size() == 10);
  const double f1 = doc["fe"]["natural_frequencies_hz"][0].get<double>();
  // Three elastic shafts: every tier is available, each with one free rotation.
  REQUIRE(doc["tiers"].size() == 7);
  CHECK(doc["tiers_unavailable"].empty());
  for (const auto& t : doc["tiers"]) {
    INFO(t["name"]);
    CHECK(t["free_rotations"] == 1);
    REQUIRE(t["static_compliance"].size() == 2);  // two meshes
    const std::string name = t["name"];
    // Tier 1 keeps only held rotations: no compliance, so no error (null, not 1).
    CHECK(t["compliance_error_vs_full"].is_null() == (name == "tier 1"));
    if (name != "tier 1" && name != "tier 2" && name != "N20 simple") {
      // Craig–Bampton and MTA keep the compliance matrix exactly (rounding: 1e-10).
      CHECK(t["compliance_error_vs_full"].get<double>() < 1e-10);
      // and reach the full model's first frequency from above (Ritz) within 1 %.
      const double f = t["natural_frequencies_hz"][0].get<double>();
      CHECK(f >= f1 * (1.0 - 1e-9));
      if (name != "tier 3") CHECK(f < 1.01 * f1);
    }
  }
  // Campbell of analysis.tier (tier 1 by default): 3 shaft lines and 3 harmonics of 2 meshes.
  const auto& campbell = doc["campbell"];
  CHECK(campbell["tier"] == "tier 1");
  CHECK(campbell["orders"].size() == 3 + 2 * 3);
  CHECK(campbell["speeds_rpm"].size() == doc["campbell"]["modes"][0]["frequency_hz"].size());
  REQUIRE_FALSE(campbell["critical_speeds"].empty());
  for (const auto& c : campbell["critical_speeds"]) {
    CHECK(c["speed_rpm"].get<double>() >= campbell["speeds_rpm"].front().get<double>());
    CHECK(c["speed_rpm"].get<double>() <= campbell["speeds_rpm"].back().get<double>());
  }
}

TEST_CASE("check prints a train in text", "[cli][train]") {
  const auto r = RunCommand(kExe + " check " + kExamples + "/two_stage_helical_reducer.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("g1-g2") != std::string::npos);
  CHECK(r.out.find("intermediate") != std::string::npos);
  CHECK(r.out.find("tier 1 (torsional, 3 DOF, 1 free rotation)") != std::string::npos);
  CHECK(r.out.find("finite elements:") != std::string::npos);
  CHECK(r.out.find("N20 MTA") != std::string::npos);
  CHECK(r.out.find("Campbell (tier 1") != std::string::npos);
}

// The two-stage reducer with a short speed sweep (3 speeds), for the sweep tests.
std::string ShortSweepReducer() {
  std::ifstream in(kExamples + "/two_stage_helical_reducer.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string at = "analysis:\n";
  const size_t pos = text.find(at);
  REQUIRE(pos != std::string::npos);
  return text.insert(pos + at.size(), "  speed_sweep: {from: 1000 rpm, to: 1600 rpm, points: 3}\n");
}

TEST_CASE("sweep on a train: JSON, CSV files, quiet when piped", "[cli][train][sweep]") {
  const TempDir dir;
  const auto file = dir.Write("reducer.yaml", ShortSweepReducer());
  const auto out = dir.path() / "out";
  const auto r = RunCommand(kExe + " sweep --json --cycles 40 --transient 20 --out " +
                            out.string() + " " + file.string());
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.err.empty());  // no progress when piped
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["schema"] == "gearnvh/2");
  CHECK(doc["tier"] == "tier 1");
  CHECK(doc["failed_speeds"] == 0);
  REQUIRE(doc["speeds_rpm"].size() == 3);
  CHECK(doc["speeds_rpm"][2].get<double>() == Approx(1600.0).epsilon(1e-12));
  CHECK(doc["meshes"] == nlohmann::json({"g1-g2", "g3-g4"}));
  for (const auto& p : doc["points"]) {
    CHECK(p["ok"] == true);
    REQUIRE(p["meshes"].size() == 2);
    for (const auto& m : p["meshes"]) {
      CHECK(m["te"]["rms"].get<double>() > 0.0);
      CHECK(m["te"]["peak_to_peak"].get<double>() >= 2.0 * m["te"]["rms"].get<double>());
      CHECK(m["mesh_force"]["max"].get<double>() >= m["mesh_force"]["mean"].get<double>());
    }
  }
  CHECK(fs::exists(out / "sweep.json"));
  const std::string meshes = testing::ReadWholeFile(out / "meshes.csv");
  CHECK(std::count(meshes.begin(), meshes.end(), '\n') == 1 + 3 * 2);
  CHECK(fs::exists(out / "loose_gears.csv"));
  // Text: a table per mesh.
  const auto text = RunCommand(kExe + " sweep --cycles 40 --transient 20 " + file.string());
  REQUIRE(text.exit_code == 0);
  CHECK(text.out.find("mesh g3-g4") != std::string::npos);
  CHECK(text.out.find("impacts/cycle") != std::string::npos);
}

TEST_CASE("sweep on a train refuses a tier it does not have", "[cli][train][sweep]") {
  const std::string file = kExamples + "/two_stage_helical_reducer.yaml";
  const auto tier = RunCommand(kExe + " sweep --tier 7 " + file);
  CHECK(tier.exit_code == 2);
  CHECK(tier.err.find("--tier") != std::string::npos);
}

TEST_CASE("malformed trains: exit 1 naming the path, the line and the rule", "[cli][train]") {
  std::ifstream in(kExamples + "/manual_transmission_idle.yaml");
  const std::string base((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string s = base;
    const size_t at = s.find(from);
    REQUIRE(at != std::string::npos);
    return s.replace(at, from.size(), to);
  };
  struct Case {
    std::string name, text, path, rule;
  };
  const std::vector<Case> cases{
      {"unknown gear in a mesh", replace("gears: [l2, o2]", "gears: [l2, o9]"), "meshes[2].gears",
       "must name a key of gears"},
      {"mesh on one shaft", replace("gears: [l2, o2]", "gears: [l2, l3]"), "meshes[2].gears",
       "same shaft"},
      {"unknown input shaft", replace("{shaft: input, value", "{shaft: inptu, value"),
       "operating.speed.shaft", "must name a key of shafts"},
      {"same hand", replace("hand: left}\n  l0", "hand: right}\n  l0"), "gears.l0.hand",
       "opposite"},
      {"bad mounting", replace("mounting: loose, teeth: 32", "mounting: idle, teeth: 32"),
       "gears.o2.mounting", "must be fixed or loose"},
      {"unknown gear key", replace("mounting: loose, teeth: 32", "mounting: loose, teth: 32"),
       "gears.o2.teth", "did you mean 'teeth'"},
      {"negative backlash", replace("backlash: 80 um", "backlash: -80 um"), "meshes[0].backlash",
       "must be > 0"},
  };
  std::ifstream in2(kExamples + "/two_stage_helical_reducer.yaml");
  const std::string reducer((std::istreambuf_iterator<char>(in2)),
                            std::istreambuf_iterator<char>());
  std::string off_shaft = reducer;
  off_shaft.replace(off_shaft.find("at: 120 mm, teeth: 19"), 10, "at: 900 mm");
  const std::vector<Case> reducer_cases{
      {"gear beyond its elastic shaft", off_shaft, "gears.g1.at", "must lie on the shaft"},
  };
  TempDir dir;
  std::vector<Case> all = cases;
  all.insert(all.end(), reducer_cases.begin(), reducer_cases.end());
  for (const Case& c : all) {
    INFO(c.name);
    const std::string file = (dir.path() / "bad.yaml").string();
    std::ofstream(file) << c.text;
    const auto r = RunCommand(kExe + " check " + file);
    INFO(r.err);
    CHECK(r.exit_code == 1);
    CHECK(r.err.find(c.path) != std::string::npos);
    CHECK(r.err.find(c.rule) != std::string::npos);
    CHECK(r.err.find("bad.yaml:") != std::string::npos);
  }
}

}  // namespace
}  // namespace gearnvh
