// Input rules a new-user trial of gear trains found missing or inconsistent (issue 20 review):
// absurd inertias, atlas parameters of a train, the segment grid, the speed and excitation-order
// limits, and messages that echo the values as written with their line.
#include <catch2/catch.hpp>
#include <string>

#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::config {
namespace {

// Three rigid shafts a -> b -> c: g1 (23) drives g2 (41) on b, g3 (19) on b drives g4 (37) on c;
// g5 (31 teeth) turns loose on c, driven by g6 (25) on b, with a drag torque.
const std::string kBase = R"(schema: gearnvh/2
name: rules train
materials:
  steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}
shafts:
  a: {inertia: 2e-3 kg*m^2}
  b: {inertia: 3e-3 kg*m^2}
  c: {inertia: 1e-3 kg*m^2}
gears:
  g1: {shaft: a, teeth: 23, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g2: {shaft: b, teeth: 41, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g3: {shaft: b, teeth: 19, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g4: {shaft: c, teeth: 37, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g6: {shaft: b, teeth: 25, module: 2 mm, face_width: 15 mm, bore_diameter: 20 mm, material: steel}
  g5: {shaft: c, mounting: loose, teeth: 31, module: 2 mm, face_width: 15 mm, bore_diameter: 30 mm, material: steel}
meshes:
  - {gears: [g1, g2], backlash: 100 um}
  - {gears: [g3, g4], backlash: 100 um}
  - {gears: [g6, g5], backlash: 100 um}
operating:
  speed: {shaft: a, value: 1000 rpm}
  loads:
    - {on: c, torque: 1 N*m}
    - {on: g5, torque: 0.2 N*m}
  excitation:
    - {order: 2, amplitude: 500 rad/s^2}
analysis:
  cycles: 50
  transient_cycles: 10
  speed_sweep: {from: 800 rpm, to: 1200 rpm, points: 2}
)";

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// The error the loader throws for `text`; fails the test when it accepts it.
InputError ErrorOf(const std::string& text) {
  try {
    LoadAnyGearboxFromString(text, "t.yaml");
  } catch (const InputError& e) {
    return e;
  }
  FAIL("accepted");
  throw std::logic_error("unreachable");
}

TEST_CASE("a body inertia above 1e9 kg m^2 is refused as written", "[loader][train]") {
  // 1e300 kg m^2 once made `check` report a NaN critical speed (an internal error).
  CHECK_NOTHROW(LoadAnyGearboxFromString(
      Replace(kBase, "b: {inertia: 3e-3 kg*m^2}", "b: {inertia: 1e9 kg*m^2}")));
  for (const std::string v : {"1e300 kg*m^2", "2e9 kg*m^2", "2e15 kg*mm^2"}) {
    INFO(v);
    const InputError e =
        ErrorOf(Replace(kBase, "b: {inertia: 3e-3 kg*m^2}", "b: {inertia: " + v + "}"));
    CHECK(e.path() == "shafts.b.inertia");
    CHECK(e.value() == "'" + v + "'");
    CHECK(e.line() == 7);
    CHECK(e.rule().find("must be <= 1e+09 kg m^2") != std::string::npos);
  }
  // A gear's own inertia override follows the same rule.
  const InputError g = ErrorOf(Replace(kBase, "g5: {shaft: c, mounting: loose,",
                                       "g5: {shaft: c, inertia: 1e300 kg*m^2, mounting: loose,"));
  CHECK(g.path() == "gears.g5.inertia");
  CHECK(g.value() == "'1e300 kg*m^2'");
}


TEST_CASE("analysis.atlas of a train names train parameters", "[loader][train]") {
  const std::string atlas =
      "  atlas:\n"
      "    x: {parameter: 'meshes[2].backlash', from: 50 um, to: 150 um, points: 3}\n"
      "    y: {parameter: 'operating.loads[1].torque', from: 0.05 N*m, to: 0.5 N*m, points: 2, "
      "scale: log}\n";
  const std::string text = kBase + atlas;
  const LoadedGearbox loaded = LoadAnyGearboxFromString(text);
  REQUIRE(loaded.train.analysis.atlas_x);
  REQUIRE(loaded.train.analysis.atlas_y);
  CHECK(loaded.train.analysis.atlas_x->parameter == "meshes[2].backlash");
  // Units as the train parameter's dimension: 50 um = 5e-5 m, 0.5 N*m (exact conversions, 1e-15).
  CHECK(loaded.train.analysis.atlas_x->range.from == Approx(5e-5).epsilon(1e-15));
  CHECK(loaded.train.analysis.atlas_y->range.to == Approx(0.5).epsilon(1e-15));
  CHECK(loaded.train.analysis.atlas_y->range.scale == AxisScale::kLog);

  // A schema-1 name is refused with the train's forms, at its line (analysis.atlas.x is line 32).
  const InputError pair = ErrorOf(Replace(text, "'meshes[2].backlash'", "mesh.backlash"));
  CHECK(pair.path() == "analysis.atlas.x.parameter");
  CHECK(pair.line() == 32);
  CHECK(pair.value() == "'mesh.backlash'");
  CHECK(pair.rule().find("meshes[i].backlash") != std::string::npos);
  // An index beyond the file's list names what the list has.
  const InputError index = ErrorOf(Replace(text, "'operating.loads[1].torque'",
                                           "'operating.loads[2].torque'"));
  CHECK(index.path() == "analysis.atlas.y.parameter");
  CHECK(index.line() == 33);
  CHECK(index.value() == "'operating.loads[2].torque'");
  CHECK(index.rule().find("0: on c, 1: on g5") != std::string::npos);
  // A value in the wrong dimension for the parameter.
  const InputError unit = ErrorOf(Replace(text, "from: 50 um", "from: 50 rpm"));
  CHECK(unit.path() == "analysis.atlas.x.from");
}

}  // namespace
}  // namespace gearnvh::config
