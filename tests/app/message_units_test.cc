// Lengths and angles in input-error messages are shown in the unit the file wrote them in (the
// value and the bound of the rule), and in mm and deg when the file wrote mm and deg or nothing
// (InputError::Quantity, config::LocatedIn). Numbers: idle_rattle.yaml's pair of 27 and 43 teeth
// of module 2 mm at 20 deg, whose base radii sum to 70 mm x cos 20 deg = 65.7785 mm.
#include <catch2/catch.hpp>
#include <string>

#include "app/load_error.h"
#include "app/loose_gear_train_yaml.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh {
namespace {

using testing::Contains;
using testing::Example;
using testing::LoadError;
using testing::Replace;

const std::string kPair = Example("idle_rattle.yaml");

std::string WithCenterDistance(const std::string& written) {
  return Replace(kPair, "  backlash: 100 um ",
                 "  center_distance: " + written + "\n  backlash: 100 um ");
}

TEST_CASE("a length rule shows the value and its bound in the unit the file wrote",
          "[loader][units]") {
  // The centre distance below the base radii: the bound 65.7785 mm in m for a length in m,
  // however the number is written, and for a plain number (SI).
  for (const std::string written : {"\"0.0034 m\"", "3.4e-3 m", "0.06"}) {
    const std::string err = LoadError(WithCenterDistance(written));
    INFO(err);
    CHECK(Contains(err, "mesh.center_distance: must exceed the sum of base radii (0.0657785 m)"));
  }
  CHECK(Contains(LoadError(WithCenterDistance("3.4e-3 m")), "got '3.4e-3 m'"));
  // Written in mm: in mm, as before.
  const std::string mm = LoadError(WithCenterDistance("60 mm"));
  INFO(mm);
  CHECK(Contains(mm,
                 "t.yaml:35: mesh.center_distance: must exceed the sum of base radii "
                 "(65.7785 mm), got '60 mm'"));

  // A module in inches: the pinion's 2 mm as 2 / 25.4 in, and the module limits [0.05, 100] mm.
  const std::string inch =
      LoadError(Replace(kPair, "teeth: 43\n    module: 2 mm", "teeth: 43\n    module: 0.1 in"));
  INFO(inch);
  CHECK(Contains(inch, "gears.wheel.module: must equal the module of gears.pinion (0.0787402 in)"));
  CHECK(Contains(inch, "got '0.1 in'"));
  const std::string huge = LoadError(
      Replace(Replace(kPair, "teeth: 43\n    module: 2 mm", "teeth: 43\n    module: 5 in"),
              "teeth: 27\n    module: 2 mm", "teeth: 27\n    module: 5 in"));
  INFO(huge);
  CHECK(Contains(huge, "gears.pinion.module: must be in [0.0019685, 3.93701] in: the tooth"));
  const std::string huge_mm = LoadError(
      Replace(Replace(kPair, "teeth: 43\n    module: 2 mm", "teeth: 43\n    module: 127 mm"),
              "teeth: 27\n    module: 2 mm", "teeth: 27\n    module: 127 mm"));
  CHECK(Contains(huge_mm, "gears.pinion.module: must be in [0.05, 100] mm"));
}

TEST_CASE("an angle rule shows the value and its bound in the unit the file wrote",
          "[loader][units]") {
  // The pressure angle's range (0, 45 deg): in rad for an angle in rad, in deg for one in deg.
  const std::string rad =
      LoadError(Replace(kPair, "pressure_angle: 20 deg", "pressure_angle: 0.9 rad"));
  INFO(rad);
  CHECK(Contains(rad, "gears.pinion.pressure_angle: must be in (0, 0.785398) rad, got '0.9 rad'"));
  const std::string deg =
      LoadError(Replace(kPair, "pressure_angle: 20 deg", "pressure_angle: 60 deg"));
  INFO(deg);
  CHECK(Contains(deg, "gears.pinion.pressure_angle: must be in (0, 45) deg, got '60 deg'"));

  // Helix angles of a helical pair: the pinion's 15 deg in the unit of the wheel's (rad here).
  const std::string helical =
      Replace(kPair, "pressure_angle: 20 deg\n    face_width",
              "pressure_angle: 20 deg\n    helix_angle: 15 deg\n    hand: right\n    face_width");
  const std::string helix = LoadError(
      Replace(helical, "teeth: 43\n", "teeth: 43\n    helix_angle: 0.2 rad\n    hand: left\n"));
  INFO(helix);
  CHECK(Contains(helix,
                 "gears.wheel.helix_angle: must equal the pinion's helix angle (0.261799 "
                 "rad): gears in mesh share it, got '0.2 rad'"));
  const std::string helix_deg = LoadError(
      Replace(helical, "teeth: 43\n", "teeth: 43\n    helix_angle: 10 deg\n    hand: left\n"));
  CHECK(Contains(helix_deg, "must equal the pinion's helix angle (15 deg)"));

  // A helical pair's module and pressure angle are the normal ones as written (2 mm, 20 deg), not
  // the transverse section's (2 / cos 15 deg = 2.07055 mm, 20.6469 deg).
  const std::string wheel = "teeth: 43\n    helix_angle: 15 deg\n    hand: left\n";
  const std::string normal_module =
      LoadError(Replace(helical, "teeth: 43\n    module: 2 mm", wheel + "    module: 2.5 mm"));
  INFO(normal_module);
  CHECK(Contains(normal_module,
                 "gears.wheel.module: must equal the module of gears.pinion (2 mm): gears in mesh "
                 "share the module, got '2.5 mm'"));
  const std::string normal_angle =
      LoadError(Replace(helical, "teeth: 43\n    module: 2 mm\n    pressure_angle: 20 deg",
                        wheel + "    module: 2 mm\n    pressure_angle: 22.5 deg"));
  INFO(normal_angle);
  CHECK(Contains(normal_angle,
                 "gears.wheel.pressure_angle: must equal the pressure angle of gears.pinion (20 "
                 "deg): gears in mesh share the pressure angle, got '22.5 deg'"));
}

TEST_CASE("a train's length and angle rules show the unit its file wrote",
          "[loader][units][train]") {
  const std::string& train = testing::kLooseGearTrainYaml;
  const std::string b = "b: {shaft: layshaft, teeth: 35, module: 2 mm,";
  const std::string inch =
      LoadError(Replace(train, b, "b: {shaft: layshaft, teeth: 35, module: 0.1 in,"));
  INFO(inch);
  CHECK(Contains(inch, "gears.b.module: must equal the module of gears.a (0.0787402 in)"));
  CHECK(Contains(inch, "got '0.1 in'"));
  // gears.a's pressure angle is the default 20 deg, shown in the unit of the angle it is compared
  // with (the error's own path).
  const std::string rad = LoadError(Replace(train, b, b + " pressure_angle: 0.4 rad,"));
  INFO(rad);
  CHECK(Contains(rad,
                 "gears.b.pressure_angle: must equal the pressure angle of gears.a (0.349066 "
                 "rad)"));
  const std::string mm =
      LoadError(Replace(train, b, "b: {shaft: layshaft, teeth: 35, module: 2.5 mm,"));
  CHECK(Contains(mm, "must equal the module of gears.a (2 mm)"));
}

TEST_CASE("outside a file the library shows lengths in mm and angles in deg", "[units]") {
  const InputError e("mesh.center_distance", 0, {"{}", {InputError::Length(0.06)}},
                     {"must be in [{#}, {#}] {unit} or at {}",
                      {InputError::Length(0.05), InputError::Length(0.07),
                       InputError::Angle(0.5, "gears.pinion.pressure_angle", 3)}});
  CHECK(std::string(e.what()) ==
        "mesh.center_distance: must be in [50, 70] mm or at 28.6 deg, got 60 mm");
  // Located: each quantity in the unit written at its path (the angle's own path here).
  const InputError located =
      e.Located(7, "", "f.yaml", [](const std::string& path, InputError::Dimension d) {
        if (d == InputError::Dimension::kLength) return std::optional<DisplayUnit>({"m", 1.0});
        if (path == "gears.pinion.pressure_angle") return std::optional<DisplayUnit>({"rad", 1.0});
        return std::optional<DisplayUnit>();
      });
  CHECK(std::string(located.what()) ==
        "f.yaml:7: mesh.center_distance: must be in [0.05, 0.07] m or at 0.5 rad, got 0.06 m");
  // Kept through a rename (a train restating a pair's rule) and a new source.
  const InputError renamed =
      located.Renamed([](const std::string& p) { return "meshes[0]" + p.substr(4); },
                      [](const std::string& r) { return r + " in meshes[0]"; });
  CHECK(renamed.path() == "meshes[0].center_distance");
  CHECK(renamed.WithSource("g.yaml").rule() ==
        "must be in [0.05, 0.07] m or at 0.5 rad in meshes[0]");
}

}  // namespace
}  // namespace gearnvh
