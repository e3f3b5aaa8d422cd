// End-to-end tests of `gearnvh check`: exit codes, messages naming the YAML path, JSON keys.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/run_command.h"
#include "support/paths.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
using testing::kExamples;

const std::string kValid = R"(schema: gearnvh/1
name: test pair
materials:
  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}
gears:
  pinion:
    teeth: 27
    module: 2 mm
    face_width: 15 mm
    bore_diameter: 25 mm
    material: steel
  wheel:
    teeth: 43
    module: 2 mm
    face_width: 15 mm
    bore_diameter: 30 mm
    material: steel
mesh:
  backlash: 100 um
operating:
  speed: 800 rpm
  torque: 0.5 N*m
)";

const std::string kShafts = R"(shafts:
  input:
    material: steel
    segments: [{length: 100 mm, outer_diameter: 30 mm}]
    gear_at: 50 mm
    bearings:
      - {at: 0 mm, radial_stiffness: 2e8 N/m, axial_stiffness: 1e8 N/m}
      - {at: 100 mm, radial_stiffness: 2e8 N/m}
)";

std::string ReplaceFirst(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  text.replace(pos, from.size(), to);
  return text;
}

struct MalformedCase {
  std::string what;
  std::string yaml;
  std::string expected_path;  // must appear in the message
  std::string expected_rule;  // must appear too ("" = not checked)
};

std::vector<MalformedCase> MalformedCases() {
  const std::string v = kValid;
  return {
      {"bad unit", ReplaceFirst(v, "module: 2 mm", "module: 2 mmm"), "gears.pinion.module",
       "unknown unit 'mmm'"},
      {"unit of the wrong dimension", ReplaceFirst(v, "100 um", "100 rpm"), "mesh.backlash",
       "unknown unit"},
      {"misspelled key", ReplaceFirst(v, "backlash:", "backlsh:"), "mesh.backlsh",
       "did you mean 'backlash'"},
      {"unknown top-level key", v + "extra: 1\n", "extra", "unknown key"},
      {"negative backlash", ReplaceFirst(v, "100 um", "-100 um"), "mesh.backlash", "must be > 0"},
      {"zero backlash", ReplaceFirst(v, "100 um", "0 um"), "mesh.backlash", "must be > 0"},
      {"teeth < 6", ReplaceFirst(v, "teeth: 27", "teeth: 4"), "gears.pinion.teeth", ">= 6"},
      {"teeth not an integer", ReplaceFirst(v, "teeth: 27", "teeth: 27.5"), "gears.pinion.teeth",
       "integer"},
      {"missing gear material",
       ReplaceFirst(v, "    bore_diameter: 30 mm\n    material: steel\n",
                    "    bore_diameter: 30 mm\n"),
       "gears.wheel.material", "required key is missing"},
      {"unknown material name", ReplaceFirst(v, "material: steel", "material: stel"),
       "gears.pinion.material", "did you mean 'steel'"},
      {"missing materials section",
       ReplaceFirst(v,
                    "materials:\n  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: "
                    "7850 kg/m^3}\n",
                    ""),
       "materials", "required key is missing"},
      {"wrong type: text for a speed", ReplaceFirst(v, "800 rpm", "fast"), "operating.speed",
       "rotational speed"},
      {"wrong type: mapping for a length", ReplaceFirst(v, "module: 2 mm", "module: {a: 1}"),
       "gears.pinion.module", "length"},
      {"duplicate key", ReplaceFirst(v, "teeth: 27\n", "teeth: 27\n    teeth: 28\n"),
       "gears.pinion.teeth", "duplicate key"},
      {"missing name", ReplaceFirst(v, "name: test pair\n", ""), "name", "required key is missing"},
      {"damping ratio above 1",
       ReplaceFirst(v, "backlash: 100 um", "backlash: 100 um\n  damping_ratio: 1.5"),
       "mesh.damping_ratio", "must be in"},
      {"Poisson ratio out of range", ReplaceFirst(v, "poisson_ratio: 0.3", "poisson_ratio: 0.7"),
       "materials.steel.poisson_ratio", "must be in"},
      {"Young's modulus without its G (206 Pa)",
       ReplaceFirst(v, "youngs_modulus: 206 GPa", "youngs_modulus: 206 Pa"),
       "materials.steel.youngs_modulus", "must be in [0.5, 1200] GPa"},
      {"density in g/cm^3 with the kg/m^3 number",
       ReplaceFirst(v, "density: 7850 kg/m^3", "density: 7850 g/cm^3"), "materials.steel.density",
       "must be in [500, 25000] kg/m^3"},
      {"pressure angle too large",
       ReplaceFirst(v, "module: 2 mm", "module: 2 mm\n    pressure_angle: 60 deg"),
       "gears.pinion.pressure_angle", "must be in"},
      {"bore larger than root", ReplaceFirst(v, "bore_diameter: 25 mm", "bore_diameter: 200 mm"),
       "gears.pinion.bore_diameter", "root diameter"},
      {"runout amplitude negative",
       ReplaceFirst(v, "    bore_diameter: 25 mm\n",
                    "    bore_diameter: 25 mm\n    runout: {amplitude: -5 um}\n"),
       "gears.pinion.runout.amplitude", "must be in"},
      {"runout without amplitude",
       ReplaceFirst(v, "    bore_diameter: 25 mm\n",
                    "    bore_diameter: 25 mm\n    runout: {phase: 10 deg}\n"),
       "gears.pinion.runout.amplitude", "required key is missing"},
      {"pitch errors of the wrong length",
       ReplaceFirst(v, "    bore_diameter: 25 mm\n",
                    "    bore_diameter: 25 mm\n    pitch_errors: [1 um, -2 um, 0 um]\n"),
       "gears.pinion.pitch_errors", "one deviation per tooth (27)"},
      {"pitch error larger than the module",
       ReplaceFirst(
           v, "    bore_diameter: 25 mm\n",
           "    bore_diameter: 25 mm\n    pitch_errors: [" +
               [] {
                 std::string list = "3 mm";
                 for (int i = 1; i < 27; ++i) list += ", 0 um";
                 return list;
               }() +
               "]\n"),
       "gears.pinion.pitch_errors[0]", "must be in"},
      {"unsupported schema version", ReplaceFirst(v, "gearnvh/1", "gearnvh/3"), "schema",
       "must be gearnvh/1 or gearnvh/2"},
      {"unknown stiffness model",
       ReplaceFirst(v, "backlash: 100 um", "backlash: 100 um\n  stiffness: {model: rectangle}"),
       "mesh.stiffness.model", "did you mean 'rectangular'"},
      {"table length mismatch",
       ReplaceFirst(v, "backlash: 100 um",
                    "backlash: 100 um\n  stiffness: {model: table, table: {phase: [0, 0.5], "
                    "stiffness: [2e8 N/m]}}"),
       "mesh.stiffness.table.stiffness", "as many entries"},
      {"tier out of range", v + "analysis: {tier: 7}\n", "analysis.tier", "1..5"},
      {"flexible tier without shafts", v + "analysis: {tier: \"N20 MTA\"}\n", "analysis.tier",
       "needs flexible shafts"},
      {"too few segments", v + "analysis: {segments_per_cycle: 2}\n", "analysis.segments_per_cycle",
       "[4, 4096]"},
      {"zero speed", ReplaceFirst(v, "800 rpm", "0 rpm"), "operating.speed", "must be > 0"},
      {"negative torque", ReplaceFirst(v, "0.5 N*m", "-0.5 N*m"), "operating.torque",
       "must be >= 0"},
      {"bearing off the shaft", v + ReplaceFirst(kShafts, "at: 100 mm", "at: 300 mm"),
       "shafts.input.bearings[1].at", "must lie on the shaft"},
      {"excitation not a list",
       ReplaceFirst(v, "torque: 0.5 N*m", "torque: 0.5 N*m\n  excitation: {order: 2}"),
       "operating.excitation", "must be a list"},
      {"a third gear", ReplaceFirst(v, "gears:\n", "gears:\n  idler: {teeth: 20}\n"), "gears.idler",
       "unknown key"},
      {"top level is a list", "- a\n- b\n", "(document)", "must be a mapping"},
      {"centre distance too small",
       ReplaceFirst(v, "backlash: 100 um", "backlash: 100 um\n  center_distance: 60 mm"),
       "mesh.center_distance", "base radii"},
      {"empty file", "", "(document)", "empty"},
      {"not YAML", "{{{: [\n  - ]: }\n", "(document)", "not valid YAML"},
      {"binary garbage", std::string("\x00\xff\xfe garbage \x01\x02", 15), "(document)", ""},
      {"shaft floats axially",
       v + ReplaceFirst(kShafts, "axial_stiffness: 1e8 N/m", "axial_stiffness: 0 N/m"),
       "shafts.input.bearings", "axial_stiffness > 0"},
      {"tip relief without length",
       ReplaceFirst(v, "    bore_diameter: 25 mm\n",
                    "    bore_diameter: 25 mm\n    tip_relief: {amount: 10 um, length: 0 mm}\n"),
       "gears.pinion.tip_relief.length", "must be > 0"},
      {"atlas parameter unknown",
       v + "analysis:\n  atlas:\n    x: {parameter: operating.sped, from: 1, to: 2, points: 3}\n   "
           " y: {parameter: mesh.backlash, from: 1 um, to: 2 um, points: 3}\n",
       "analysis.atlas.x.parameter", "did you mean 'operating.speed'"},
  };
}

TEST_CASE("malformed gearbox files: exit code 1 and a message naming the path",
          "[cli][malformed]") {
  const auto cases = MalformedCases();
  REQUIRE(cases.size() >= 25);
  TempDir dir;
  for (size_t i = 0; i < cases.size(); ++i) {
    const MalformedCase& c = cases[i];
    SECTION(c.what) {
      const auto file = dir.Write("case" + std::to_string(i) + ".yaml", c.yaml);
      const auto r = RunCommand(kExe + " check " + file.string());
      INFO("case: " << c.what << "\nstderr: " << r.err);
      CHECK(r.exit_code == 1);
      CHECK(r.out.empty());
      CHECK(r.err.find(c.expected_path) != std::string::npos);
      CHECK(r.err.find(file.filename().string()) != std::string::npos);
      if (!c.expected_rule.empty()) CHECK(r.err.find(c.expected_rule) != std::string::npos);
    }
  }
}

TEST_CASE("check and simulate refuse a tier the model cannot have with the same message",
          "[cli][malformed]") {
  TempDir dir;
  const auto file = dir.Write("mta.yaml", kValid + "analysis: {tier: \"N20 MTA\", cycles: 10}\n");
  const auto check = RunCommand(kExe + " check " + file.string());
  const auto simulate = RunCommand(kExe + " simulate " + file.string());
  INFO("check: " << check.err << "simulate: " << simulate.err);
  CHECK(check.exit_code == 1);
  CHECK(simulate.exit_code == 1);
  CHECK(check.err.find("analysis.tier: needs flexible shafts") != std::string::npos);
  CHECK(check.err == simulate.err);
}

TEST_CASE("error messages give the line of the offending value", "[cli][malformed]") {
  TempDir dir;
  const auto file = dir.Write("neg.yaml", ReplaceFirst(kValid, "100 um", "-100 um"));
  const auto r = RunCommand(kExe + " check " + file.string());
  CHECK(r.exit_code == 1);
  CHECK(r.err.find("neg.yaml:19: mesh.backlash: must be > 0, got '-100 um'") != std::string::npos);
}

TEST_CASE("usage errors exit 2, help exits 0", "[cli]") {
  CHECK(RunCommand(kExe).exit_code == 2);
  CHECK(RunCommand(kExe + " frobnicate").exit_code == 2);
  CHECK(RunCommand(kExe + " check").exit_code == 2);
  CHECK(RunCommand(kExe + " check /nonexistent/file.yaml").exit_code == 1);  // input, not usage
  CHECK(RunCommand(kExe + " check --bogus " + kExamples + "/idle_rattle.yaml").exit_code == 2);
  const auto help = RunCommand(kExe + " --help");
  CHECK(help.exit_code == 0);
  CHECK(help.out.find("check") != std::string::npos);
  const auto check_help = RunCommand(kExe + " check --help");
  CHECK(check_help.exit_code == 0);
  CHECK(check_help.out.find("--json") != std::string::npos);
}

TEST_CASE("check succeeds on every bundled example", "[cli]") {
  const auto r = RunCommand(kExe + " check " + kExamples + "/*.yaml");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out.find("contact ratio") != std::string::npos);
}

TEST_CASE("check --json has the documented keys in SI units", "[cli][json]") {
  const auto r = RunCommand(kExe + " check --json " + kExamples + "/idle_rattle.yaml");
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["name"] == "Passenger-car 5th gear, idle rattle");
  const auto& g = doc["geometry"];
  CHECK(g["center_distance"].get<double>() == Approx(0.070).epsilon(1e-12));
  CHECK(g["mesh_frequency_hz"].get<double>() == Approx(27 * 800 / 60.0).epsilon(1e-12));
  CHECK(g["pinion"]["tip_radius"].get<double>() == Approx(0.029).epsilon(1e-12));
  CHECK(g["wheel"]["root_radius"].get<double>() == Approx(0.043 - 0.0025).epsilon(1e-12));
  CHECK(g["contact_ratio"].get<double>() > 1.5);
  CHECK(g["pinion"].contains("base_radius"));
  // Component model keys (issue 3), in SI units.
  const auto& mesh = doc["mesh"];
  CHECK(mesh["contact_ratio"].get<double>() == g["contact_ratio"].get<double>());
  for (const char* key : {"mean", "min", "max", "single_pair_mean", "double_pair_mean"}) {
    INFO(key);
    CHECK(mesh["stiffness"][key].get<double>() > 1e7);  // N/m: steel spur pairs are 1e8..1e9
    CHECK(mesh["stiffness"][key].get<double>() < 1e10);
  }
  CHECK(mesh["stiffness"]["min"].get<double>() <= mesh["stiffness"]["mean"].get<double>());
  CHECK(mesh["stiffness"]["mean"].get<double>() <= mesh["stiffness"]["max"].get<double>());
  CHECK(mesh["lste_peak_to_peak"].get<double>() > 0.0);
  CHECK(mesh["load_sharing_max"].get<double>() <= 1.0 + 1e-12);
  const auto& fe = doc["fe"];
  CHECK(fe["dofs"].get<int>() == 6 * fe["nodes"].get<int>());
  REQUIRE(fe["natural_frequencies_hz"].size() == 10);
  for (size_t i = 1; i < 10; ++i) {
    CHECK(fe["natural_frequencies_hz"][i].get<double>() >=
          fe["natural_frequencies_hz"][i - 1].get<double>());
  }
}

TEST_CASE("check on the flexible example reports the shaft FE model", "[cli][json]") {
  const auto r = RunCommand(kExe + " check --json " + kExamples + "/flexible_shafts.yaml");
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["fe"]["flexible_shafts"].get<bool>());
  CHECK(doc["fe"]["nodes"].get<int>() > 40);
  CHECK(doc["fe"]["rigid_body_modes"].get<int>() == 1);
  CHECK(doc["fe"]["natural_frequencies_hz"][0].get<double>() > 10.0);
  // Tiers (issue 4): all seven on a flexible model, CB exact, simple truncation's error shown.
  const auto& tiers = doc["tiers"];
  REQUIRE(tiers.size() == 7);
  CHECK(doc["tiers_unavailable"].empty());
  for (const auto& t : tiers) {
    INFO(t["name"]);
    // The solver's state: positions, velocities and the constant slot (no engine order, no
    // errors: no input slot).
    CHECK(t["state_dim"].get<int>() == 2 * t["dof"].get<int>() + 1);
    CHECK(t["natural_frequencies_hz"].size() > 0);
    const std::string name = t["name"];
    if (name == "N20 simple") CHECK(std::abs(t["compliance_error_vs_full"].get<double>()) > 1e-6);
    if (name == "tier 3" || name == "tier 4" || name == "N40 full" || name == "N20 MTA") {
      CHECK(std::abs(t["compliance_error_vs_full"].get<double>()) < 1e-10);
    }
  }
}

TEST_CASE("check on a rigid-shaft example lists tiers 1-3 and says why not the others",
          "[cli][json]") {
  const auto r = RunCommand(kExe + " check --json " + kExamples + "/idle_rattle.yaml");
  REQUIRE(r.exit_code == 0);
  const auto doc = nlohmann::json::parse(r.out);
  CHECK(doc["tiers"].size() == 3);
  CHECK(doc["tiers_unavailable"].size() == 4);
  CHECK(doc["tiers"][0]["dof"] == 2);
  CHECK(doc["tiers"][0]["name"] == "tier 1");
  // Tier 1 has no mesh compliance (rigid shafts, held rotations): no error, not -100 %.
  CHECK(doc["tiers"][0]["compliance_error_vs_full"].is_null());
  CHECK(doc["tiers"][1]["compliance_error_vs_full"].is_number());
}

TEST_CASE("check's text table shows n/a for tier 1's compliance error and not -1", "[cli]") {
  const auto r = RunCommand(kExe + " check " + kExamples + "/idle_rattle.yaml");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const size_t row = r.out.find("\n  tier 1 ");
  REQUIRE(row != std::string::npos);
  const std::string line = r.out.substr(row + 1, r.out.find('\n', row + 1) - row - 1);
  INFO(line);
  CHECK(line.find("n/a") != std::string::npos);
  CHECK(line.find("-1.00e+00") == std::string::npos);
}

TEST_CASE("check on a helical pair says n/a for the single-pair zone it does not have", "[cli]") {
  // Overlap ratio 15 mm sin 30° / (pi 2 mm) = 1.19: one pair never carries the load alone.
  const TempDir dir;
  std::string text =
      ReplaceFirst(kValid, "teeth: 27\n", "teeth: 27\n    helix_angle: 30 deg\n    hand: left\n");
  text = ReplaceFirst(text, "teeth: 43\n", "teeth: 43\n    helix_angle: 30 deg\n    hand: right\n");
  const auto file = dir.Write("helical.yaml", text).string();
  const auto r = RunCommand(kExe + " check " + file);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  const size_t row = r.out.find("single-pair mean");
  REQUIRE(row != std::string::npos);
  const std::string line = r.out.substr(row, r.out.find('\n', row) - row);
  CHECK(line.find("n/a") != std::string::npos);
  CHECK(line.find(" 0 N/m") == std::string::npos);
  const auto j = RunCommand(kExe + " check --json " + file);
  REQUIRE(j.exit_code == 0);
  const auto stiffness = nlohmann::json::parse(j.out)["mesh"]["stiffness"];
  CHECK(stiffness["single_pair_mean"].is_null());
  CHECK(stiffness["mean"].get<double>() > 0.0);
}

TEST_CASE("a batch with one bad file checks the others and exits 1", "[cli][json]") {
  TempDir dir;
  const auto bad = dir.Write("bad.yaml", ReplaceFirst(kValid, "teeth: 27", "teeth: 3"));
  const auto r = RunCommand(kExe + " check --json " + kExamples + "/idle_rattle.yaml " +
                            bad.string() + " " + kExamples + "/industrial_whine.yaml");
  CHECK(r.exit_code == 1);
  const auto doc = nlohmann::json::parse(r.out);
  REQUIRE(doc.is_array());
  REQUIRE(doc.size() == 3);
  CHECK(doc[0].contains("geometry"));
  CHECK(doc[1]["error"].get<std::string>().find("gears.pinion.teeth") != std::string::npos);
  CHECK(doc[2].contains("geometry"));
}

}  // namespace
}  // namespace gearnvh
