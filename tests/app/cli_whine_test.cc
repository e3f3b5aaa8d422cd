// End-to-end tests of `gearnvh whine`: a pair and a train, JSON, files, and refused options.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/example_variant.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::kExamples;
using testing::kExe;
using testing::RunCommand;
using testing::TempDir;

// The index of the line at `order` in a whine document's `lines`.
size_t LineIndex(const nlohmann::json& doc, double order) {
  for (size_t l = 0; l < doc["lines"].size(); ++l) {
    if (std::abs(doc["lines"][l]["order"].get<double>() - order) <= 1e-9 * order) return l;
  }
  FAIL("no line at order " << order);
  return 0;
}

size_t CountLines(const std::filesystem::path& file) {
  std::ifstream in(file);
  size_t n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST_CASE("whine on a pair: at low speed the runout line is the runout itself", "[cli][whine]") {
  // 30..60 rpm: mesh orders far below the mesh resonance, so the mesh follows its input
  // quasi-statically, delta -> e: the 1x pinion line equals the runout amplitude to (f / f_n)^2.
  const TempDir dir;
  const std::string relief = "    tip_relief: {amount: 20 um, length: 8 mm}\n";
  const auto file = dir.Write(
      "runout.yaml", testing::ExampleVariantText(
                         "industrial_whine.yaml",
                         {{"speed_sweep: {from: 300 rpm, to: 4500 rpm, points: 43}",
                           "speed_sweep: {from: 30 rpm, to: 60 rpm, points: 2}"},
                          {relief, relief + "    runout: {amplitude: 10 um, phase: 30 deg}\n"}}));
  const auto run = RunCommand(kExe + " whine --json --speeds 4 " + file.string());
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto doc = nlohmann::json::parse(run.out);
  CHECK(doc["model"] == "mean");
  REQUIRE(doc["speeds_rpm"].size() == 4);
  CHECK(doc["speeds_rpm"][0].get<double>() == Approx(30.0));
  REQUIRE(doc["meshes"].size() == 1);
  const auto& mesh = doc["meshes"][0];
  CHECK(mesh["name"] == "pinion-wheel");
  const size_t runout = LineIndex(doc, 1.0);
  CHECK(doc["lines"][runout]["kind"] == "shaft_order");
  for (const auto& te : mesh["orders"][runout]["te_amplitude_m"])
    CHECK(te.get<double>() == Approx(10e-6).epsilon(1e-4));
  CHECK(doc["bearings"].empty());  // tier 1
  CHECK_FALSE(mesh["contact_loss"][0].get<bool>());
}

TEST_CASE("whine on a train: --out writes the JSON and both CSV files, --uff the tracks",
          "[cli][whine]") {
  const TempDir dir;
  const auto out = dir.path() / "whine";
  const auto uff = dir.path() / "whine.uff";
  const auto run =
      RunCommand(kExe + " whine --tier 3 --speeds 12 --out " + out.string() + " --uff " +
                 uff.string() + " " + kExamples + "/two_stage_helical_reducer.yaml");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  CHECK(run.out.find("mesh g1-g2") != std::string::npos);
  CHECK(run.out.find("bearings: peak force amplitude") != std::string::npos);
  std::ifstream in(out / "whine.json");
  const auto doc = nlohmann::json::parse(in);
  REQUIRE(doc["meshes"].size() == 2);
  const size_t lines = doc["lines"].size();
  CHECK(lines >= 6);  // mesh orders 1..3 of both meshes
  for (const auto& m : doc["meshes"]) {
    REQUIRE(m["orders"].size() == lines);
    CHECK(m["orders"][0]["te_amplitude_m"].size() == 12);
  }
  REQUIRE_FALSE(doc["bearings"].empty());
  CHECK(doc["bearings"][0]["orders"][0]["force_amplitude_n"]["x"].size() == 12);
  // A row per speed, mesh and line, and per speed, bearing and line, under a header.
  CHECK(CountLines(out / "whine_meshes.csv") == 12 * 2 * lines + 1);
  CHECK(CountLines(out / "whine_bearings.csv") == 12 * doc["bearings"].size() * lines + 1);
  // Dataset 58 per mesh and line: its TE track and its force track.
  std::ifstream tracks(uff);
  size_t datasets = 0;
  for (std::string line; std::getline(tracks, line);) datasets += line == "    58" ? 1 : 0;
  CHECK(datasets == 2 * 2 * lines);
}

TEST_CASE("whine refuses bad options by name", "[cli][whine]") {
  const std::string file = kExamples + "/industrial_whine.yaml";
  const auto speeds = RunCommand(kExe + " whine --speeds 1 " + file);
  CHECK(speeds.exit_code == 2);
  CHECK(speeds.err.find("--speeds") != std::string::npos);
  const auto tier = RunCommand(kExe + " whine --tier 5 " + file);
  CHECK(tier.exit_code == 2);  // as simulate: a tier the gearbox cannot have is a usage error
  CHECK(tier.err.find("--tier") != std::string::npos);
}

}  // namespace
}  // namespace gearnvh

namespace gearnvh {
namespace {

TEST_CASE("whine --housing reads a transfer table and names its errors by file and line",
          "[cli][whine]") {
  const TempDir dir;
  const std::string reducer = kExamples + "/two_stage_helical_reducer.yaml";
  const auto table = dir.Write("housing.csv",
                               "# accelerance at the mounting foot\n"
                               "frequency_hz,bearing,direction,real,imag\n"
                               "0,input.bearings[0],x,1e-3,0\n"
                               "5000,input.bearings[0],x,1e-3,0\n"
                               "0,output.bearings[1],y,0,2e-3\n"
                               "5000,output.bearings[1],y,0,2e-3\n");
  const auto run = RunCommand(kExe + " whine --tier 3 --speeds 6 --json --housing " +
                              table.string() + " " + reducer);
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto doc = nlohmann::json::parse(run.out);
  REQUIRE(doc["housing"].is_object());
  const auto& orders = doc["housing"]["orders"];
  REQUIRE(orders.size() == doc["lines"].size());
  // Each line's response is bounded by the sum of |H| |F| over the two curves (triangle
  // inequality) and is that sum's level in dB re 1e-6 m/s^2.
  for (size_t l = 0; l < orders.size(); ++l) {
    for (size_t s = 0; s < 6; ++s) {
      // A line above the table's 5000 Hz has no response (null).
      const double hz = orders[l]["order"].get<double>() * doc["speeds_rpm"][s].get<double>() / 60;
      if (hz > 5000.0) {
        CHECK(orders[l]["acceleration_m_s2"][s].is_null());
        continue;
      }
      const double a = orders[l]["acceleration_m_s2"][s].get<double>();
      double bound = 0.0;
      for (const auto& b : doc["bearings"]) {
        if (b["name"] == "input.bearings[0]")
          bound += 1e-3 * b["orders"][l]["force_amplitude_n"]["x"][s].get<double>();
        if (b["name"] == "output.bearings[1]")
          bound += 2e-3 * b["orders"][l]["force_amplitude_n"]["y"][s].get<double>();
      }
      CHECK(a <= bound * (1.0 + 1e-12));
      CHECK(orders[l]["db_re_1e-6_m_s2"][s].get<double>() ==
            Approx(20.0 * std::log10(a / 1e-6)).epsilon(1e-12));
    }
  }
  struct Bad {
    std::string text, expected;
  };
  for (const Bad& bad :
       {Bad{"frequency,bearing,direction,real,imag\n", "housing.csv:1: header"},
        Bad{"frequency_hz,bearing,direction,real,imag\n0,input.bearings[0],w,1,0\n",
            "housing.csv:2: direction"},
        Bad{"frequency_hz,bearing,direction,real,imag\n9,input.bearings[0],x,1,0\n"
            "3,input.bearings[0],x,1,0\n",
            "housing.csv:3: frequency_hz"},
        Bad{"frequency_hz,bearing,direction,real,imag\n0,shaft9.bearings[0],x,1,0\n"
            "1,shaft9.bearings[0],x,1,0\n",
            "housing.csv:2: bearing"},
        Bad{"frequency_hz,bearing,direction,real,imag\n0,input.bearings[0],x,abc,0\n",
            "housing.csv:2: real"},
        Bad{"frequency_hz,bearing,direction,real,imag\n0,input.bearings[99999999999],x,1,0\n",
            "housing.csv:2: bearing"}}) {
    const auto bad_table = dir.Write("housing.csv", bad.text);
    const auto refused = RunCommand(kExe + " whine --tier 3 --speeds 2 --housing " +
                                    bad_table.string() + " " + reducer);
    INFO(bad.text << refused.err);
    CHECK(refused.exit_code == 1);
    CHECK(refused.err.find(bad.expected) != std::string::npos);
  }
}

TEST_CASE("whine --housing takes a spreadsheet's export and a curve that carries no force",
          "[cli][whine]") {
  // A byte-order mark, quoted cells, spaces after the commas and an underflowing number are read;
  // at tier 2 a z curve carries no force (no axial DOF): a response of 0, with no dB level.
  const TempDir dir;
  const auto table =
      dir.Write("export.csv",
                "\xEF\xBB\xBF\"frequency_hz\", \"bearing\", \"direction\", \"real\", "
                "\"imag\"\r\n"
                "0, \"input.bearings[0]\", z, 1e-3, 1e-320\r\n"
                "10000, \"input.bearings[0]\", z, 1e-3, 0\r\n");
  const auto run = RunCommand(kExe + " whine --tier 2 --speeds 3 --json --housing " +
                              table.string() + " " + kExamples + "/two_stage_helical_reducer.yaml");
  INFO(run.err);
  REQUIRE(run.exit_code == 0);
  const auto doc = nlohmann::json::parse(run.out);
  const auto& first = doc["housing"]["orders"][0];
  CHECK(first["acceleration_m_s2"][0].get<double>() == 0.0);
  CHECK(first["db_re_1e-6_m_s2"][0].is_null());
  const auto text = RunCommand(kExe + " whine --tier 2 --speeds 3 --housing " + table.string() +
                               " " + kExamples + "/two_stage_helical_reducer.yaml");
  CHECK(text.exit_code == 0);
  CHECK(text.out.find("no response (its curves carry no force)") != std::string::npos);
}

}  // namespace
}  // namespace gearnvh
