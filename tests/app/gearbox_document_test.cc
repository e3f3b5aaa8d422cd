#include "config/gearbox_document.h"

#include <catch2/catch.hpp>
#include <numbers>

#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::config {
namespace {

const std::string kExample = std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml";

TEST_CASE("a document loads as the loader does and edits by schema path", "[document]") {
  GearboxDocument doc = GearboxDocument::FromFile(kExample);
  CHECK_FALSE(doc.Edited());
  const GearboxSpec original = LoadGearboxFile(kExample);
  CHECK(doc.Load().pair->operating.torque == original.operating.torque);
  // A quantity with units as written, and a bare number as SI: the same double either way.
  const GearboxSpec with_units = *doc.SetScalar("operating.torque", "0.3 N*m").pair;
  const GearboxSpec si = *doc.SetScalar("operating.torque", "0.3").pair;
  CHECK(with_units.operating.torque == si.operating.torque);
  CHECK(si.operating.torque == 0.3);
  CHECK(doc.Edited());
  CHECK(doc.Get("operating.torque") == "0.3");
  // List entries by [i] or .i; whole lists as YAML/JSON.
  CHECK(doc.SetScalar("operating.excitation[0].amplitude", "900 rad/s^2")
            .pair->operating.excitation[0]
            .amplitude == 900.0);
  CHECK(doc.Get("operating.excitation.0.amplitude") == "900 rad/s^2");
  const GearboxSpec two =
      *doc.SetYaml("operating.excitation",
                   R"([{"order": 2, "amplitude": 100}, {order: 4, amplitude: 50}])")
           .pair;
  REQUIRE(two.operating.excitation.size() == 2);
  CHECK(two.operating.excitation[1].order == 4.0);
  // Everything else is untouched by the edits.
  CHECK(two.mesh.backlash == original.mesh.backlash);
  CHECK(two.pinion.inertia == original.pinion.inertia);
}

TEST_CASE("a train document edits by schema path and keeps its schema", "[document]") {
  const std::string file = std::string(GEARNVH_EXAMPLES_DIR) + "/two_stage_helical_reducer.yaml";
  GearboxDocument doc = GearboxDocument::FromFile(file);
  const LoadedGearbox original = LoadAnyGearboxFile(file);
  REQUIRE(doc.Load().schema == 2);
  const LoadedGearbox edited = doc.SetScalar("operating.speed.value", "1234 rpm");
  CHECK(edited.schema == 2);
  // rpm to rad/s: the loader's conversion of the same text, so equal to rounding (one product).
  CHECK(edited.train.operating.speed ==
        Approx(1234.0 * 2.0 * std::numbers::pi / 60.0).epsilon(1e-15));
  CHECK(edited.train.meshes.size() == original.train.meshes.size());
  const std::string before = doc.Text();
  try {
    doc.SetScalar("schema", "gearnvh/1");
    FAIL("an edit changed the schema");
  } catch (const InputError& e) {
    CHECK(e.path() == "schema");
    CHECK(std::string(e.what()).find("cannot change the schema") != std::string::npos);
  }
  CHECK(doc.Text() == before);
  // A pair without a schema line is gearnvh/1: writing that line changes nothing.
  std::string text = ReadGearboxText(kExample);
  const size_t line = text.find("schema: gearnvh/1\n");
  REQUIRE(line != std::string::npos);
  text.erase(line, std::string("schema: gearnvh/1\n").size());
  GearboxDocument pair = GearboxDocument::FromText(text, "pair.yaml");
  CHECK(pair.SetScalar("schema", "gearnvh/1").schema == 1);
}

TEST_CASE("a bad edit names the path and rule and leaves the document unchanged", "[document]") {
  GearboxDocument doc = GearboxDocument::FromFile(kExample);
  const std::string before = doc.Text();
  try {
    doc.SetScalar("mesh.backlash", "-5 um");
    FAIL("a negative backlash was accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "mesh.backlash");
    CHECK(e.value() == "'-5 um'");
    CHECK(e.source() == kExample + " (edited)");
  }
  CHECK_THROWS_AS(doc.SetScalar("operating.excitation[5].order", "2"), InputError);
  CHECK_THROWS_AS(doc.SetScalar("name.first", "x"), InputError);  // through a scalar
  CHECK_THROWS_AS(doc.SetScalar("operating..torque", "1"), InputError);
  CHECK_THROWS_AS(doc.SetYaml("operating", "{speed: [unclosed"), InputError);
  CHECK_THROWS_AS(doc.Get("operating.nothing"), InputError);
  CHECK(doc.Text() == before);
  CHECK_FALSE(doc.Edited());
}

TEST_CASE("flow data is re-emitted in block style so errors point at a line", "[document]") {
  const std::string json =
      R"({"schema": "gearnvh/1", "name": "x", "materials": {"steel": {"youngs_modulus": "206 GPa",)"
      R"( "poisson_ratio": 0.3, "density": "7850 kg/m^3"}}, "gears": {"pinion": 1}})";
  const GearboxDocument doc = GearboxDocument::FromData(json, "<dict>");
  CHECK(doc.Text().find('\n') < doc.Text().size() - 1);  // more than one line
  try {
    doc.Load();
    FAIL("an incomplete gearbox loaded");
  } catch (const InputError& e) {
    CHECK(e.source() == "<dict>");
    INFO(e.what());
    CHECK(e.path() == "gears.pinion");
    CHECK(e.line() > 1);
  }
}

}  // namespace
}  // namespace gearnvh::config
