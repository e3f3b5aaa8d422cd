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
  const auto run = RunCommand(kExe + " whine --tier 3 --speeds 12 --out " + out.string() +
                              " --uff " + uff.string() + " " + kExamples +
                              "/two_stage_helical_reducer.yaml");
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
