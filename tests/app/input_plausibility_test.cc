// Issue 36 through the loader and the command line: implausible lengths in either schema, the
// gear a mismatch is blamed on, shaft and gear names, one centre distance per shaft pair, the
// size of a train, warnings on missing loads, oversized and control-character input in messages,
// and list indexes of an edit path.
#include <catch2/catch.hpp>
#include <string>

#include "app/load_error.h"
#include "app/three_shaft_train_yaml.h"
#include "config/gearbox_document.h"
#include "config/gearbox_loader.h"
#include "gearnvh/analysis/train_load_warnings.h"
#include "gearnvh/model/input_error.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::Contains;
using testing::kExe;
using testing::kThreeShaftTrainYaml;
using testing::LoadError;
using testing::Replace;

std::string IdleRattle() { return testing::Example("idle_rattle.yaml"); }

TEST_CASE("absurd backlash and face width are refused in both schemas", "[loader][limits]") {
  for (const std::string backlash : {"80", "80 mm"}) {
    const std::string pair =
        LoadError(Replace(IdleRattle(), "backlash: 100 um", "backlash: " + backlash));
    INFO(pair);
    CHECK(Contains(pair, "mesh.backlash: must be at most "));
    CHECK(Contains(pair, "of the tooth thickness at the pitch circle"));
    CHECK(Contains(pair, "got '" + backlash + "'"));
  }
  const std::string mm = LoadError(Replace(IdleRattle(), "backlash: 100 um", "backlash: 80 mm"));
  CHECK(Contains(mm, "must be at most 0.785398 mm, 0.25 of the tooth thickness"));
  const std::string face = LoadError(Replace(IdleRattle(), "face_width: 15 mm", "face_width: 20"));
  INFO(face);
  CHECK(Contains(face,
                 "gears.pinion.face_width: gives b/m = 10000 face widths per module; must be "
                 "in [0.3, 300] (here [0.0006, 0.6] m)"));
  CHECK(Contains(face, "got '20'"));

  const std::string train =
      LoadError(Replace(kThreeShaftTrainYaml, "backlash: 100 um", "backlash: 80"));
  INFO(train);
  CHECK(Contains(train, "meshes[0].backlash: must be at most "));
  const std::string train_face =
      LoadError(Replace(kThreeShaftTrainYaml, "teeth: 41, module: 2 mm, face_width: 15 mm",
                        "teeth: 41, module: 2 mm, face_width: 20"));
  CHECK(Contains(train_face, "gears.g2.face_width: gives b/m = 10000"));
  for (const std::string example :
       {"flexible_shafts.yaml", "idle_rattle.yaml", "industrial_whine.yaml",
        "manual_transmission_idle.yaml", "two_stage_helical_reducer.yaml"}) {
    INFO(example);
    CHECK_NOTHROW(config::LoadAnyGearboxFile(std::string(GEARNVH_EXAMPLES_DIR) + "/" + example));
  }
}

TEST_CASE("a module or helix angle without its unit is blamed on its own gear", "[loader][train]") {
  // g1 is the first gear of meshes[0]: its mate g2 used to be named ("must equal the module of
  // gears.g1 (2000 mm)").
  const std::string module = LoadError(Replace(kThreeShaftTrainYaml, "module: 2 mm", "module: 2"));
  INFO(module);
  CHECK(Contains(module, "gears.g1.module: must be in [5e-05, 0.1] m"));
  CHECK(Contains(module, "got '2'"));
  const std::string helix = LoadError(Replace(kThreeShaftTrainYaml, "material: steel}",
                                              "material: steel, "
                                              "helix_angle: 28, hand: left}"));
  INFO(helix);
  CHECK(Contains(helix, "gears.g1.helix_angle: must be in [0, 0.785398) rad, got '28'"));
}

TEST_CASE("a gear may not share a shaft's name", "[loader][train]") {
  std::string text = Replace(kThreeShaftTrainYaml, "  g4: {shaft: c", "  c: {shaft: c");
  text = Replace(text, "[g3, g4]", "[g3, c]");
  const std::string error = LoadError(text);
  INFO(error);
  CHECK(Contains(error,
                 "gears.c: has the name of shafts.c: a name belongs to one shaft or one "
                 "gear"));
}

TEST_CASE("meshes between the same two shafts need one centre distance", "[loader][train]") {
  // g6 (20) on b with g5 (37) loose on c: 57 mm beside g3-g4's 56 mm.
  const std::string text = Replace(
      Replace(kThreeShaftTrainYaml, "  g4: {shaft: c",
              "  g6: {shaft: b, teeth: 20, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, "
              "material: steel}\n  g5: {shaft: c, mounting: loose, teeth: 37, module: 2 mm, "
              "face_width: 15 mm, bore_diameter: 20 mm, material: steel}\n  g4: {shaft: c"),
      "  - {gears: [g3, g4], backlash: 100 um}\n",
      "  - {gears: [g3, g4], backlash: 100 um}\n  - {gears: [g6, g5], backlash: 100 um}\n");
  const std::string error = LoadError(text);
  INFO(error);
  CHECK(Contains(error,
                 "meshes[2].gears: joins shafts 'b' and 'c' at a centre distance of 57 mm, "
                 "but meshes[1] (g3-g4) joins them at 56 mm"));
  CHECK(LoadError(Replace(text,
                          "teeth: 37, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, "
                          "material: steel}\n  g4",
                          "teeth: 36, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, "
                          "material: steel}\n  g4"))
            .empty());
}

TEST_CASE("a train beyond the size limit is refused before any work", "[loader][train]") {
  std::string meshes;
  for (int i = 0; i < 128; ++i) meshes += "  - {gears: [g1, g2], backlash: 100 um}\n";
  const std::string error =
      LoadError(Replace(kThreeShaftTrainYaml, "meshes:\n", "meshes:\n" + meshes));
  INFO(error);
  CHECK(Contains(error, "meshes: must have at most 128 meshes"));
  CHECK(Contains(error, "got 130 meshes"));
}

TEST_CASE("a train without a load, or without one on its output, is warned about",
          "[train][warnings]") {
  const auto warnings = [](const std::string& text) {
    const TrainSpec spec = config::LoadAnyGearboxFromString(text).train;
    return gearnvh::TrainLoadWarnings(spec, AnalyseTrainTopology(spec));
  };
  CHECK(warnings(kThreeShaftTrainYaml).empty());
  const std::string no_load =
      Replace(kThreeShaftTrainYaml, "  loads:\n    - {on: c, torque: 1 N*m}\n", "");
  REQUIRE(warnings(no_load).size() == 1);
  CHECK(warnings(no_load)[0].rfind("operating.loads: the train has no load", 0) == 0);
  const std::string on_b = Replace(kThreeShaftTrainYaml, "{on: c, torque", "{on: b, torque");
  REQUIRE(warnings(on_b).size() == 1);
  CHECK(warnings(on_b)[0].rfind("operating.loads: no load on the output shaft 'c'", 0) == 0);
  // In neutral behind a flywheel coupled to a: a drives only g4, loose on the fixed shaft c.
  // No shaft is the train's output; a, reached from the flywheel through the coupling only, is
  // not called one.
  const std::string neutral = R"(schema: gearnvh/2
name: neutral behind a flywheel
materials:
  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}
shafts:
  flywheel: {inertia: 0.1 kg*m^2}
  a: {inertia: 2e-3 kg*m^2}
  c: {inertia: 1e-3 kg*m^2, fixed: true}
gears:
  g1: {shaft: a, teeth: 23, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g4: {shaft: c, mounting: loose, teeth: 37, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm,
       material: steel}
meshes:
  - {gears: [g1, g4], backlash: 100 um}
couplings:
  damper: {between: [flywheel, a], stiffness: 1000}
operating:
  speed: {shaft: flywheel, value: 1000 rpm}
  loads:
    - {on: g4, torque: 0.2 N*m}
)";
  CHECK(warnings(neutral).empty());

  testing::TempDir dir;
  const auto check = testing::RunCommand(kExe + " check " + dir.Write("t.yaml", no_load).string());
  INFO(check.out << check.err);
  CHECK(check.exit_code == 0);
  CHECK(Contains(check.out, "warning: operating.loads: the train has no load"));
}

TEST_CASE("messages cut a long value and name an oversized key", "[loader][messages]") {
  const std::string huge(1000000, 'x');
  const std::string value =
      LoadError(Replace(IdleRattle(), "backlash: 100 um", "backlash: " + huge));
  INFO(value.substr(0, 300));
  CHECK(value.size() < 1000);
  CHECK(Contains(value, "got 'xxxxxxxxxx"));
  CHECK(Contains(value, "… (1000002 bytes)"));  // with its quotes

  const std::string key(200000, 'k');
  const std::string long_key = LoadError(Replace(IdleRattle(), "mesh:\n", key + ": 1\nmesh:\n"));
  INFO(long_key.substr(0, 300));
  CHECK(long_key.size() < 1000);
  CHECK(Contains(long_key, "t.yaml:34: (document): has a key of 200000 bytes"));
  CHECK(Contains(long_key, "YAML allows a key of at most 1024 characters"));
}

TEST_CASE("control characters in names are refused and never echoed raw", "[loader][messages]") {
  for (const std::string escape : {"\\x07", "\\0", "\\t", "\\x85"}) {
    const std::string gear = LoadError(
        Replace(kThreeShaftTrainYaml, "  g4: {shaft: c", "  \"g4" + escape + "\": {shaft: c"));
    INFO(gear);
    CHECK(Contains(gear, "must not contain control characters"));
    CHECK(gear.find_first_of(std::string("\a\t\n", 3) + std::string(1, '\0')) == std::string::npos);
    CHECK(gear.find("\xC2\x85") == std::string::npos);
  }
  const std::string bell = LoadError(Replace(
      IdleRattle(), "name: Passenger-car 5th gear, idle rattle", "name: \"\\x07Passenger\""));
  INFO(bell);
  CHECK(Contains(bell, "t.yaml:12: name: must not contain control characters (character 1 is one"));
  CHECK(Contains(bell, "got '\\x07Passenger"));
}

TEST_CASE("an edit path's oversized list index is an input error", "[document]") {
  config::GearboxDocument doc = config::GearboxDocument::FromText(kThreeShaftTrainYaml);
  try {
    doc.SetScalar("meshes[99999999999999999999].backlash", "80 um");
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "meshes[99999999999999999999].backlash");
    CHECK(Contains(e.rule(), "is not a list index: at most 9 digits"));
  }
  CHECK_THROWS_AS(doc.SetScalar("meshes.99999999999999999999.backlash", "80 um"), InputError);
  CHECK_THROWS_WITH(doc.SetScalar("meshes[999999999].backlash", "80 um"),
                    Catch::Contains("list index out of range"));
}

}  // namespace
}  // namespace gearnvh
