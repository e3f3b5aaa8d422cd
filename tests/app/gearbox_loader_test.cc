#include "config/gearbox_loader.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/input_error.h"
#include "load_error.h"

namespace gearnvh::config {
namespace {

TEST_CASE("every bundled example loads and validates", "[loader]") {
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(GEARNVH_EXAMPLES_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    INFO(entry.path());
    CHECK_NOTHROW(LoadAnyGearboxFile(entry.path().string()));
    ++count;
  }
  CHECK(count >= 3);
}

TEST_CASE("the rattle example reads into SI with defaults", "[loader]") {
  const GearboxSpec s = LoadGearboxFile(std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml");
  const double tol = 4 * std::numeric_limits<double>::epsilon();
  CHECK(s.pinion.teeth == 27);
  CHECK(s.wheel.teeth == 43);
  CHECK(s.pinion.module == Approx(2e-3).epsilon(tol));
  CHECK(s.mesh.backlash == Approx(100e-6).epsilon(tol));
  CHECK(s.operating.speed == Approx(800 * 2 * std::numbers::pi / 60).epsilon(tol));
  CHECK(s.operating.excitation.size() == 1);
  CHECK(s.operating.excitation[0].order == 2);
  CHECK(s.pinion.addendum_coefficient == 1.0);   // default
  CHECK(s.pinion.dedendum_coefficient == 1.25);  // default
  CHECK(s.materials.at("steel").youngs_modulus == Approx(206e9).epsilon(tol));
  CHECK(s.analysis.atlas_x->parameter == "operating.speed");
  CHECK(std::holds_alternative<PotentialEnergyStiffness>(s.mesh.stiffness));
}

TEST_CASE("a pair's excitation order is an acceleration (the default), other kinds are refused",
          "[loader]") {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "- {order: 2,";
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  const auto with = [&](const std::string& kind) {
    std::string t = text;
    t.replace(at, from.size(), "- {kind: " + kind + ", order: 2,");
    return t;
  };
  CHECK(LoadGearboxFromString(with("acceleration")) == LoadGearboxFromString(text));
  for (const std::string kind : {"torque", "motion"}) {
    try {
      LoadGearboxFromString(with(kind));
      FAIL("kind: " << kind << " was accepted");
    } catch (const InputError& e) {
      CHECK(e.path() == "operating.excitation[0].kind");
      // Motion is not built for any gearbox; a torque order needs a train's shafts.
      CHECK_THAT(e.rule(), Catch::Contains(kind == "motion" ? "not built yet" : "gear train"));
    }
  }
}

TEST_CASE("stiffness overrides and tiers parse", "[loader]") {
  const std::string base = R"(
name: t
materials: {steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}}
gears:
  pinion: {teeth: 20, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
  wheel:  {teeth: 30, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
operating: {speed: 1000 rpm, torque: 1 N*m}
)";
  const GearboxSpec r = LoadGearboxFromString(base + R"(
mesh:
  backlash: 0.1 mm
  stiffness: {model: rectangular, rectangular: {single: 2e8 N/m, double: 3.4e8 N/m, contact_ratio: 1.6}}
analysis: {tier: "N20 MTA"}
)");
  const auto& rect = std::get<RectangularStiffness>(r.mesh.stiffness);
  CHECK(rect.double_pair == 3.4e8);
  CHECK(r.analysis.tier == Tier::kN20Mta);
  const GearboxSpec f = LoadGearboxFromString(base + R"(
mesh:
  backlash: 0.1 mm
  stiffness: {model: fourier, fourier: {mean: 2.7e8 N/m, cos: [3e7 N/m], sin: [1e7]}}
analysis: {tier: 3}
)");
  CHECK(std::get<FourierStiffness>(f.mesh.stiffness).sin_coefficients[0] == 1e7);
  CHECK(f.analysis.tier == Tier::kTier3);
}

TEST_CASE("errors carry path, line and value as written", "[loader]") {
  try {
    LoadGearboxFromString(R"(name: x
materials: {steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}}
gears:
  pinion: {teeth: 20, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
  wheel:  {teeth: 30, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
mesh:
  backlash: -100 um
operating: {speed: 1000 rpm, torque: 1 N*m}
)",
                          "x.yaml");
    FAIL("accepted negative backlash");
  } catch (const InputError& e) {
    CHECK(e.path() == "mesh.backlash");
    CHECK(e.line() == 7);
    CHECK(std::string(e.what()) == "x.yaml:7: mesh.backlash: must be > 0, got '-100 um'");
  }
}

TEST_CASE("syntax errors name deep nesting, a tab in the indentation and a too large integer",
          "[loader]") {
  using testing::Example;
  using testing::LoadError;
  using testing::Replace;
  const std::string rattle = Example("idle_rattle.yaml");
  // yaml-cpp stops at 500 levels with the message "bad file".
  const std::string deep =
      LoadError("name: " + std::string(1000, '[') + std::string(1000, ']') + "\n");
  CHECK(deep.rfind("t.yaml:1: (document): not valid YAML here: lists and mappings nested ", 0) ==
        0);
  CHECK(deep.find("levels deep, more than the parser allows") != std::string::npos);
  CHECK(deep.find("bad file") == std::string::npos);
  // A tab before `teeth:` (line 27 of the example): yaml-cpp says "illegal map value".
  const std::string tab = LoadError(Replace(rattle, "    teeth: 43", "\tteeth: 43"));
  CHECK(tab.find("(line 27 is indented with a tab: YAML indents with spaces only)") !=
        std::string::npos);
  // An error without a tab nearby gets no such note.
  CHECK(LoadError("a: [1, 2\n").find("tab") == std::string::npos);
  // 1e12 is an integer: the rule broken is its size.
  CHECK(LoadError(Replace(rattle, "cycles: 2000", "cycles: 1000000000000")) ==
        "t.yaml:48: analysis.cycles: must be an integer between -2e9 and 2e9, got "
        "'1000000000000'");
  CHECK(LoadError(Replace(rattle, "cycles: 2000", "cycles: 20.5")) ==
        "t.yaml:48: analysis.cycles: must be an integer, got '20.5'");
}

TEST_CASE("a YAML merge key is named as such and not as an unknown key", "[loader]") {
  using testing::Example;
  using testing::LoadError;
  using testing::Replace;
  // An anchored pinion merged into the wheel: yaml-cpp hands the loader a key named "<<".
  const std::string merged =
      Replace(Replace(Example("idle_rattle.yaml"), "  pinion:\n", "  pinion: &p\n"), "  wheel:\n",
              "  wheel:\n    <<: *p\n");
  CHECK(LoadError(merged) ==
        "t.yaml:27: gears.wheel.<<: YAML merge keys (<<) are not supported; write the keys out");
}

TEST_CASE("closest-key suggestions", "[loader]") {
  CHECK(ClosestMatch("backlsh", {"backlash", "damping_ratio"}) == "backlash");
  CHECK(ClosestMatch("modul", {"module", "teeth"}) == "module");
  CHECK(ClosestMatch("zzzzzz", {"module", "teeth"}).empty());
}

TEST_CASE("each loaded document keeps its own source locations", "[loader]") {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The same text under the same source name, the second shifted down by three comment lines: an
  // error raised after both loads is located by the locations of the load it came from.
  const LoadedGearbox first = LoadAnyGearboxFromString(text, "same.yaml");
  const LoadedGearbox second = LoadAnyGearboxFromString("#\n#\n#\n" + text, "same.yaml");
  const SourceLocations::Location at = first.locations.Find("analysis.tier");
  REQUIRE(at.line > 0);
  CHECK(at.raw == "1");
  CHECK(second.locations.Find("analysis.tier").line == at.line + 3);
  const InputError late("analysis.tier", 0, "", "a rule checked after loading");
  const InputError in_first = LocatedIn(late, first.locations, "same.yaml");
  const InputError in_second = LocatedIn(late, second.locations, "same.yaml");
  CHECK(in_first.line() == at.line);
  CHECK(in_second.line() == at.line + 3);
  CHECK(in_first.value() == "'1'");
  CHECK(std::string(in_second.what()) ==
        "same.yaml:" + std::to_string(at.line + 3) +
            ": analysis.tier: a rule checked after loading, got '1'");
  // A path under a written key takes that key's line; nothing loaded: no line.
  CHECK(LocatedIn(InputError("analysis.tier.x", 0, "", "r"), first.locations, "same.yaml").line() ==
        at.line);
  CHECK(LocatedIn(late, SourceLocations{}, "same.yaml").line() == 0);
  // An error of another source is not located with these locations.
  CHECK(LocatedIn(late.WithSource("other.yaml"), first.locations, "same.yaml").line() == 0);
}

}  // namespace
}  // namespace gearnvh::config

namespace gearnvh::config {
namespace {

// A loaded spur pair 20:30 (m = 2 mm, alpha = 20 deg) whose torque is given on `on`.
GearboxSpec TorquePair(const std::string& torque, const std::string& on) {
  return LoadGearboxFromString(R"(
name: torque
materials: {steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}}
gears:
  pinion: {teeth: 20, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
  wheel:  {teeth: 30, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
mesh: {backlash: 100 um}
operating: {speed: 1000 rpm, torque: )" +
                               torque + (on.empty() ? "" : ", torque_on: " + on) + "}\n");
}

TEST_CASE("operating.torque_on: a pinion torque loads the mesh with T1 / r_b1", "[loader]") {
  // Closed form: r_b = m z cos(alpha) / 2; the static mesh force along the line of action is the
  // torque over the base radius of the gear it acts on. Tolerance 1e-12 relative: the same
  // arithmetic in a different order.
  const double alpha = 20.0 * std::numbers::pi / 180.0;
  const double rb1 = 0.5 * 2e-3 * 20 * std::cos(alpha), rb2 = 0.5 * 2e-3 * 30 * std::cos(alpha);
  const GearboxSpec wheel_default = TorquePair("30 N*m", "");
  CHECK(wheel_default.operating.torque_on == TorqueOn::kWheel);
  const GearboxSpec pinion = TorquePair("20 N*m", "pinion");
  CHECK(pinion.operating.torque_on == TorqueOn::kPinion);
  CHECK(pinion.operating.torque == Approx(20.0).epsilon(1e-15));  // kept as given
  CHECK(pinion.WheelTorque() == Approx(20.0 * rb2 / rb1).epsilon(1e-12));

  const ComponentModel on_pinion = BuildComponentModel(pinion);
  CHECK(on_pinion.cycle.load == Approx(20.0 / rb1).epsilon(1e-12));
  // The equivalent wheel torque T2 = T1 r_b2 / r_b1 = 30 N m gives the same model: the same mesh
  // force and the same generalized forces (same sign: the drive flank is loaded).
  const ComponentModel on_wheel = BuildComponentModel(wheel_default);
  CHECK(on_wheel.cycle.load == Approx(30.0 / rb2).epsilon(1e-12));
  CHECK(on_pinion.cycle.load == Approx(on_wheel.cycle.load).epsilon(1e-12));
  REQUIRE(on_pinion.static_force.size() == on_wheel.static_force.size());
  CHECK((on_pinion.static_force - on_wheel.static_force).norm() <=
        1e-12 * on_wheel.static_force.norm());
  CHECK(on_pinion.static_force[on_pinion.PinionDof(kThz)] == Approx(20.0).epsilon(1e-12));
  CHECK(on_pinion.static_force[on_pinion.WheelDof(kThz)] == Approx(30.0).epsilon(1e-12));
  CHECK(on_pinion.mesh_summary.mean == Approx(on_wheel.mesh_summary.mean).epsilon(1e-12));

  CHECK(TorquePair("30 N*m", "wheel").WheelTorque() == 30.0);
  try {
    TorquePair("1 N*m", "shaft");
    FAIL("accepted torque_on: shaft");
  } catch (const InputError& e) {
    CHECK(e.path() == "operating.torque_on");
    CHECK(e.rule() == "must be wheel or pinion");
  }
}

// The text of a pair with an atlas and a speed sweep whose axes carry `scale` entries (empty: no
// entry).
std::string ScaledAxesYaml(const std::string& sweep_scale, const std::string& torque_from,
                           const std::string& torque_scale) {
  auto entry = [](const std::string& scale) {
    return scale.empty() ? std::string() : ", scale: " + scale;
  };
  return R"(name: x
materials: {steel: {youngs_modulus: 206 GPa, poisson_ratio: 0.3, density: 7850 kg/m^3}}
gears:
  pinion: {teeth: 20, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
  wheel:  {teeth: 30, module: 2 mm, face_width: 10 mm, bore_diameter: 10 mm, material: steel}
mesh: {backlash: 100 um}
operating: {speed: 1000 rpm, torque: 1 N*m}
analysis:
  speed_sweep: {from: 300 rpm, to: 6000 rpm, points: 17)" +
         entry(sweep_scale) + R"(}
  atlas:
    x: {parameter: operating.speed, from: 600 rpm, to: 3000 rpm, points: 5}
    y: {parameter: operating.torque, from: )" +
         torque_from + R"(, to: 5 N*m, points: 12)" + entry(torque_scale) + R"(}
)";
}

GearboxSpec ScaledAxes(const std::string& sweep_scale, const std::string& torque_from,
                       const std::string& torque_scale) {
  return LoadGearboxFromString(ScaledAxesYaml(sweep_scale, torque_from, torque_scale), "x.yaml");
}

TEST_CASE("scale: log spaces sweep and atlas points geometrically, linear stays the default",
          "[loader]") {
  const GearboxSpec linear = ScaledAxes("", "0.05 N*m", "");
  CHECK(linear.analysis.speed_sweep.scale == AxisScale::kLinear);
  CHECK(linear.analysis.atlas_y->range.scale == AxisScale::kLinear);
  const GearboxSpec log = ScaledAxes("log", "0.05 N*m", "log");
  CHECK(log.analysis.atlas_x->range.scale == AxisScale::kLinear);  // not given: linear
  for (const SweepRange* r : {&log.analysis.speed_sweep, &log.analysis.atlas_y->range}) {
    REQUIRE(r->scale == AxisScale::kLog);
    // Closed form: consecutive points in the ratio q = (to / from)^(1 / (n - 1)); 1e-12
    // relative allows the rounding of pow over at most 16 steps (a few ulps each).
    const double q = std::exp(std::log(r->to / r->from) / (r->points - 1));
    CHECK(r->Point(0) == r->from);
    CHECK(r->Point(r->points - 1) == r->to);
    for (int i = 0; i + 1 < r->points; ++i) {
      INFO("point " << i);
      CHECK(r->Point(i + 1) / r->Point(i) == Approx(q).epsilon(1e-12));
      CHECK(r->Point(i) == Approx(r->from * std::pow(q, i)).epsilon(1e-12));
    }
  }
  // 0.05..5 N m in 12 points: a decade every 11/2 steps, 0.5 N m exactly in the middle of
  // log10 (between points 5 and 6: their geometric mean).
  const SweepRange& t = log.analysis.atlas_y->range;
  CHECK(std::sqrt(t.Point(5) * t.Point(6)) == Approx(0.5).epsilon(1e-12));
  // The linear grid: even differences (1e-12 relative: one rounding per point).
  const SweepRange& l = linear.analysis.atlas_y->range;
  for (int i = 0; i + 1 < l.points; ++i) {
    CHECK(l.Point(i + 1) - l.Point(i) == Approx((5.0 - 0.05) / 11.0).epsilon(1e-12));
  }
}

TEST_CASE("scale: log needs a positive range, and an unknown scale is named", "[loader]") {
  try {
    ScaledAxes("", "0 N*m", "log");
    FAIL("accepted a log axis from 0");
  } catch (const InputError& e) {
    CHECK(e.path() == "analysis.atlas.y.from");
    CHECK(std::string(e.what()).find("must be > 0 with scale: log") != std::string::npos);
    CHECK(std::string(e.what()).find("'0 N*m'") != std::string::npos);
  }
  try {
    ScaledAxes("logarithmic", "0.05 N*m", "");
    FAIL("accepted scale: logarithmic");
  } catch (const InputError& e) {
    CHECK(e.path() == "analysis.speed_sweep.scale");
    CHECK(std::string(e.what()).find("must be linear or log, got 'logarithmic'") !=
          std::string::npos);
  }
  // A range that does not rise names `from` by its path: its number would be in SI (rad/s for
  // the rpm written).
  try {
    LoadGearboxFromString(
        testing::Replace(ScaledAxesYaml("", "0.05 N*m", ""), "from: 300 rpm, to: 6000 rpm",
                         "from: 500 rpm, to: 500 rpm"),
        "x.yaml");
    FAIL("accepted a sweep from 500 rpm to 500 rpm");
  } catch (const InputError& e) {
    CHECK(e.path() == "analysis.speed_sweep.to");
    const std::string what = e.what();
    CHECK(what.find("must be greater than from (analysis.speed_sweep.from)") != std::string::npos);
    CHECK(what.find("'500 rpm'") != std::string::npos);
    CHECK(what.find("52.3") == std::string::npos);
  }
}

}  // namespace
}  // namespace gearnvh::config

namespace gearnvh {
namespace {

TEST_CASE("a train mesh's center_line_angle is read in angle units, default 0", "[loader][train]") {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/manual_transmission_idle.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The example gives every mesh its angle; drop the first one's (default 0), turn the second.
  auto replace = [&](const std::string& from, const std::string& to) {
    const size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    text.replace(at, from.size(), to);
  };
  replace("backlash: 80 um, center_line_angle: -90 deg", "backlash: 80 um");
  replace("[l1, o1], backlash: 100 um, center_line_angle: 90 deg",
          "[l1, o1], backlash: 100 um, center_line_angle: 180 deg");
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(text);
  REQUIRE(loaded.schema == 2);
  CHECK(loaded.train.meshes[0].center_line_angle == 0.0);
  CHECK(loaded.train.meshes[1].center_line_angle == Approx(std::numbers::pi).epsilon(1e-15));
  CHECK(loaded.train.meshes[2].center_line_angle == Approx(0.5 * std::numbers::pi).epsilon(1e-15));
  replace("center_line_angle: 180 deg", "center_line_angle: 3 mm");
  CHECK_THROWS_AS(config::LoadAnyGearboxFromString(text), InputError);
}

TEST_CASE("a train mesh's effective_mass is bodies (default) or gears, a schema-1 file gears",
          "[loader][train]") {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/manual_transmission_idle.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string from = "backlash: 80 um, center_line_angle: -90 deg";
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  const auto with = [&](const std::string& value) {
    std::string t = text;
    t.replace(at, from.size(), from + ", effective_mass: " + value);
    return t;
  };
  const config::LoadedGearbox plain = config::LoadAnyGearboxFromString(text);
  CHECK(plain.train.meshes[0].effective_mass == MeshEffectiveMass::kBodies);
  const config::LoadedGearbox gears = config::LoadAnyGearboxFromString(with("gears"));
  CHECK(gears.train.meshes[0].effective_mass == MeshEffectiveMass::kGears);
  CHECK(gears.train.meshes[1].effective_mass == MeshEffectiveMass::kBodies);
  CHECK(config::LoadAnyGearboxFromString(with("bodies")).train.meshes[0].effective_mass ==
        MeshEffectiveMass::kBodies);
  try {
    config::LoadAnyGearboxFromString(with("shafts"));
    FAIL("effective_mass: shafts was accepted");
  } catch (const InputError& e) {
    CHECK_THAT(e.what(), Catch::Contains("meshes[0].effective_mass") && Catch::Contains("shafts") &&
                             Catch::Contains("bodies or gears"));
  }
  // A schema-1 file is read into the train with the gears' rule (its contract).
  std::ifstream pair_in(std::string(GEARNVH_EXAMPLES_DIR) + "/flexible_shafts.yaml");
  const std::string pair_text((std::istreambuf_iterator<char>(pair_in)),
                              std::istreambuf_iterator<char>());
  const config::LoadedGearbox pair = config::LoadAnyGearboxFromString(pair_text);
  REQUIRE(pair.schema == 1);
  CHECK(pair.train.meshes[0].effective_mass == MeshEffectiveMass::kGears);
}

}  // namespace
}  // namespace gearnvh
