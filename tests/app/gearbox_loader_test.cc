#include "config/gearbox_loader.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "gearnvh/model/component_model.h"
#include "gearnvh/model/input_error.h"

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

TEST_CASE("closest-key suggestions", "[loader]") {
  CHECK(ClosestMatch("backlsh", {"backlash", "damping_ratio"}) == "backlash");
  CHECK(ClosestMatch("modul", {"module", "teeth"}) == "module");
  CHECK(ClosestMatch("zzzzzz", {"module", "teeth"}).empty());
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

}  // namespace
}  // namespace gearnvh
