#include "config/gearbox_loader.h"

#include <catch2/catch.hpp>
#include <filesystem>
#include <numbers>

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
