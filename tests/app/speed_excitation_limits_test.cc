// The speed and excitation-order limits of pairs and trains (docs/gearbox-yaml.md, "Limits"), the
// units of their messages, and the run-length limit of atlas, tiers and orbits.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "app/loose_gear_train_yaml.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

const std::string kExe = GEARNVH_EXE;
constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);

std::string Example(const std::string& name) {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/" + name);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

// The message of the InputError loading `text` throws ("" when it loads).
std::string LoadError(const std::string& text) {
  try {
    (void)config::LoadAnyGearboxFromString(text, "t.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// idle_rattle.yaml: spur pinion, 27 teeth of module 2 mm, so its pitch radius is 27 mm and the
// 200 m/s pitch-line limit is 200 / 0.027 rad/s = 7407.4 rad/s = 70735.5 rpm.
constexpr double kPairLimitRadS = 200.0 / 0.027;

TEST_CASE("a pair's speed is limited by a pitch-line velocity of 200 m/s, in the unit written",
          "[loader][limits]") {
  const std::string text = Example("idle_rattle.yaml");
  const std::string rpm = LoadError(Replace(text, "speed: 800 rpm", "speed: 1e30 rpm"));
  INFO(rpm);
  CHECK(Contains(rpm, "t.yaml:40: operating.speed: gives the mesh a pitch-line velocity of"));
  CHECK(Contains(rpm, "above the limit of 200 m/s (a speed of 70735.5 rpm here)"));
  CHECK(Contains(rpm, "got '1e30 rpm'"));
  // The same speed written in rad/s: the limit in rad/s.
  const std::string rad_s = LoadError(Replace(text, "speed: 800 rpm", "speed: 1e5 rad/s"));
  INFO(rad_s);
  CHECK(Contains(rad_s, "(a speed of 7407.41 rad/s here)"));
  CHECK(Contains(rad_s, "got '1e5 rad/s'"));
  // Either side of the limit (0.1 % margins, far above rounding of the 6-digit speeds).
  CHECK(LoadError(Replace(text, "speed: 800 rpm",
                          "speed: " + std::to_string(0.999 * kPairLimitRadS * kRpm) + " rpm"))
            .empty());
  CHECK(Contains(
      LoadError(Replace(text, "speed: 800 rpm",
                        "speed: " + std::to_string(1.001 * kPairLimitRadS * kRpm) + " rpm")),
      "operating.speed: gives the mesh a pitch-line velocity of 200.2 m/s"));
  // A written sweep's end is held to the same limit, in its own unit.
  const std::string sweep =
      LoadError(Replace(text, "to: 3000 rpm, points: 25", "to: 8000 rad/s, points: 25"));
  INFO(sweep);
  CHECK(
      Contains(sweep, "analysis.speed_sweep.to: gives the mesh a pitch-line velocity of 216 m/s"));
  CHECK(Contains(sweep, "(a speed of 7407.41 rad/s here)"));
}

// The loose-gear train: its fastest mesh is a-b on the input shaft (21 teeth of module 2 mm:
// r = 21 mm, 0.021 m/s per rad/s; c-d runs at 0.6 x 19 mm, e-f at 0.6 x 25 mm), so the limit is
// 200 / 0.021 rad/s = 90945.7 rpm.
TEST_CASE("a train's input speed is limited by its fastest mesh's pitch-line velocity",
          "[loader][limits][train]") {
  const std::string err =
      LoadError(Replace(testing::kLooseGearTrainYaml, "value: 1000 rpm", "value: 1e30 rpm"));
  INFO(err);
  CHECK(Contains(err, "operating.speed.value: gives meshes[0] (a-b) a pitch-line velocity of"));
  CHECK(Contains(err, "(a speed of 90945.7 rpm here)"));
  CHECK(Contains(err, "got '1e30 rpm'"));
  CHECK(LoadError(Replace(testing::kLooseGearTrainYaml, "value: 1000 rpm", "value: 90000 rpm"))
            .empty());
}

TEST_CASE("speeds in the excitation rule's message are in the unit the speed was written in",
          "[loader][limits]") {
  // a / (order x speed) = 1e6 / (2 x 83.776 rad/s) = 5968 rad/s = 56990 rpm > 800 rpm.
  const std::string text =
      Replace(Example("idle_rattle.yaml"), "amplitude: 1500 rad/s^2", "amplitude: 1e6 rad/s^2");
  const std::string err = LoadError(text);
  INFO(err);
  CHECK(Contains(err, "= 56993.2 rpm exceed the mean speed 800 rpm"));
  const std::string rad_s = LoadError(Replace(text, "speed: 800 rpm", "speed: 83.7758 rad/s"));
  INFO(rad_s);
  CHECK(Contains(rad_s, "exceed the mean speed 83.7758 rad/s"));
  // A train's input shaft likewise.
  const std::string train = LoadError(
      Replace(testing::kLooseGearTrainYaml, "amplitude: 1000 rad/s^2", "amplitude: 1e7 rad/s^2"));
  INFO(train);
  CHECK(Contains(train, "exceed its mean speed 1000 rpm"));
}

// The loaded pair's model, or the message of the InputError loading or building it throws.
std::string LoadOrBuildError(const std::string& text) {
  try {
    (void)BuildComponentModel(*config::LoadAnyGearboxFromString(text, "t.yaml").pair);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("gear-size rules give lengths in mm and angles in deg, as gear files write them",
          "[loader][limits]") {
  const std::string text = Example("idle_rattle.yaml");
  // The wheel's module (line 28) against the pinion's 2 mm: not "0.002 m".
  const std::string module = LoadOrBuildError(
      Replace(text, "teeth: 43\n    module: 2 mm", "teeth: 43\n    module: 2.5 mm"));
  INFO(module);
  CHECK(Contains(module, "must equal the module of gears.pinion (2 mm)"));
  // Helix angles: the pinion's 15 deg, not 0.261799 rad.
  const std::string helix = LoadOrBuildError(Replace(
      Replace(text, "pressure_angle: 20 deg\n    face_width",
              "pressure_angle: 20 deg\n    helix_angle: 15 deg\n    hand: right\n    face_width"),
      "teeth: 43\n", "teeth: 43\n    helix_angle: 10 deg\n    hand: left\n"));
  INFO(helix);
  CHECK(Contains(helix, "must equal the pinion's helix angle (15 deg)"));
  // A bore wider than the root circle: the root diameter in mm (z m - 2.5 m = 49 mm).
  const std::string bore =
      LoadOrBuildError(Replace(text, "bore_diameter: 25 mm", "bore_diameter: 60 mm"));
  INFO(bore);
  CHECK(Contains(bore, "must be smaller than the root diameter (49 mm)"));
}

TEST_CASE("an excitation order the segment grid cannot resolve is refused", "[model][limits]") {
  GearboxSpec spec = *config::LoadAnyGearboxFromString(Example("idle_rattle.yaml")).pair;
  const double longest = LongestSegment(BuildComponentModel(spec).segmentation);
  // The segment grid does not depend on the orders, so the largest order resolved with 8
  // segments per period is z1 / (8 f_max).
  const double highest = 27.0 / (8.0 * longest);
  REQUIRE(highest > 2.0);
  spec.operating.excitation[0].order = 0.99 * highest;
  CHECK_NOTHROW(BuildComponentModel(spec));
  spec.operating.excitation[0].order = 1.01 * highest;
  try {
    (void)BuildComponentModel(spec);
    FAIL("an order beyond the grid was accepted");
  } catch (const InputError& e) {
    CHECK(e.path() == "operating.excitation[0].order");
    CHECK(Contains(e.rule(), "spans 7.92 segments of the mesh"));
    CHECK(Contains(e.rule(), "raise analysis.segments_per_cycle (now 32) to about 33 or more"));
  }
}

TEST_CASE("a train refuses an order its finest mesh cannot resolve, at the order's line",
          "[cli][limits][train]") {
  TrainSpec spec = config::LoadAnyGearboxFromString(testing::kLooseGearTrainYaml).train;
  const GearTrain train = BuildGearTrain(spec);
  // Segments per input revolution of each mesh: z_a |w_a / w_in| / f_max.
  double finest = 0.0;
  for (const TrainMeshModel& m : train.meshes) {
    const double ratio =
        std::abs(train.topology.bodies[static_cast<size_t>(m.body_a)].speed) / spec.operating.speed;
    finest = std::max(finest, m.pair.a.teeth * ratio / LongestSegment(m.segmentation));
  }
  const double highest = finest / 8.0;
  spec.operating.excitation[0].order = 0.99 * highest;
  CHECK_NOTHROW(BuildGearTrain(spec));
  spec.operating.excitation[0].order = 1.01 * highest;
  CHECK_THROWS_WITH(BuildGearTrain(spec), Catch::Contains("operating.excitation[0].order"));

  TempDir dir;
  const auto file =
      dir.Write("order.yaml", Replace(testing::kLooseGearTrainYaml, "order: 2,", "order: 500,"));
  const auto run = RunCommand(kExe + " check " + file.string());
  INFO(run.err);
  CHECK(run.exit_code == 1);
  CHECK(Contains(run.err,
                 "order.yaml:26: operating.excitation[0].order: is too high for the "
                 "segment grid"));
  CHECK(Contains(run.err, "got '500'"));
}

TEST_CASE("atlas, tiers and orbits hold their run counts to the 3600 s limit", "[cli][limits]") {
  // idle_rattle.yaml at 800 rpm: f_mesh = 27 x 800 / 60 = 360 Hz, so 3600 s is 1,296,000 cycles.
  TempDir dir;
  const std::string example = std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml";
  const auto train = dir.Write("train.yaml", testing::kLooseGearTrainYaml);
  for (const std::string& file : {example, train.string()}) {
    for (const std::string& command :
         {std::string(" atlas --x operating.speed=600rpm:800rpm:2 "
                      "--y mesh.backlash=50um:100um:2 --transient 2000000 --out "),
          std::string(" tiers --transient 2000000 --out "),
          std::string(" orbits --transient 2000000 --out ")}) {
      if (file == train.string() && command.find("atlas") != std::string::npos) continue;
      const auto out = dir.path() / "out";
      const auto run = RunCommand(kExe + command + out.string() + " " + file);
      INFO(command << file << "\n" << run.err);
      CHECK(run.exit_code == 2);
      CHECK(Contains(run.err, "--transient: makes the "));
      CHECK(Contains(run.err, "the limit is 3600 s"));
      // Nothing written: refused before any result.
      CHECK((!std::filesystem::exists(out) || std::filesystem::is_empty(out)));
    }
  }
  // The train's atlas, on its own parameter names; the lowest speed of the axis decides.
  const auto out = dir.path() / "train-atlas";
  const auto run = RunCommand(kExe +
                              " atlas --x operating.speed=100rpm:1000rpm:2 --y "
                              "meshes[0].backlash=50um:100um:2 --transient 500000 "
                              "--out " +
                              out.string() + " " + train.string());
  INFO(run.err);
  CHECK(run.exit_code == 2);
  CHECK(Contains(run.err, "at 100 rpm"));
  CHECK_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace gearnvh
