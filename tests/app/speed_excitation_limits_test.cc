// The speed and excitation-order limits of pairs and trains (docs/gearbox-yaml.md, "Limits"), the
// units of their messages, and the run-length limit of atlas, tiers and orbits.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "app/load_error.h"
#include "app/loose_gear_train_yaml.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "support/paths.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using testing::RunCommand;
using testing::TempDir;

using testing::kExe;
constexpr double kRpmPerRadPerSecond = 60.0 / (2.0 * std::numbers::pi);

using testing::Contains;
using testing::Example;
using testing::LoadError;
using testing::Replace;

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
                          "speed: " + std::to_string(0.999 * kPairLimitRadS * kRpmPerRadPerSecond) + " rpm"))
            .empty());
  CHECK(Contains(
      LoadError(Replace(text, "speed: 800 rpm",
                        "speed: " + std::to_string(1.001 * kPairLimitRadS * kRpmPerRadPerSecond) + " rpm")),
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

TEST_CASE("a file's atlas axis over operating.speed is held to the pitch-line limit",
          "[loader][limits]") {
  const std::string err = LoadError(Replace(
      Example("idle_rattle.yaml"), "x: {parameter: operating.speed,  from: 600 rpm,  to: 3000 rpm",
      "x: {parameter: operating.speed,  from: 600 rpm,  to: 1e6 rpm"));
  INFO(err);
  CHECK(Contains(err, "t.yaml:52: analysis.atlas.x.to: gives the mesh a pitch-line velocity of"));
  CHECK(Contains(err, "(a speed of 70735.5 rpm here)"));
  CHECK(Contains(err, "got '1e6 rpm'"));
}

// idle_rattle.yaml with a 400-tooth pinion (r = 0.4 m): the limit is 200 / 0.4 = 500 rad/s =
// 4774.65 rpm, below the default sweep's 6000 rpm (at which the pitch line runs at 251.3 m/s).
TEST_CASE("the default speed sweep is clipped to the pitch-line limit, with a note",
          "[loader][limits]") {
  std::string text = Replace(Example("idle_rattle.yaml"), "teeth: 27", "teeth: 400");
  text = Replace(text, "teeth: 43", "teeth: 430");
  // Written sweep and atlas removed: the defaults apply.
  text = text.substr(0, text.find("  speed_sweep:"));
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(text, "t.yaml");
  const SweepRange& sweep = loaded.pair->analysis.speed_sweep;
  // The clipped top sits a relative 1e-9 below the limit (so rounding cannot cross it).
  CHECK(sweep.to == Approx(500.0).epsilon(1e-8));
  CHECK(sweep.to <= 500.0);
  CHECK(sweep.from == Approx(500.0 / kRpmPerRadPerSecond).epsilon(1e-12));  // the default's 500 rpm stays
  CHECK(sweep.points == 56);
  INFO(loaded.sweep_note);
  CHECK(Contains(loaded.sweep_note,
                 "analysis.speed_sweep is not written, and the default sweep 500 rpm to 6000 rpm "
                 "would run the mesh above the pitch-line velocity limit of 200 m/s (at 251.3 "
                 "m/s): sweeping 500 rpm to 4774.65 rpm instead"));
  // The train of the same pair carries the clipped sweep too.
  CHECK(loaded.train.analysis.speed_sweep.to == sweep.to);
  // Within the limit (the example's 27 teeth): the default sweep is left alone, without a note.
  const std::string small = Example("idle_rattle.yaml");
  const config::LoadedGearbox unclipped =
      config::LoadAnyGearboxFromString(small.substr(0, small.find("  speed_sweep:")), "t.yaml");
  CHECK(unclipped.sweep_note.empty());
  CHECK(unclipped.pair->analysis.speed_sweep.to == Approx(6000.0 / kRpmPerRadPerSecond).epsilon(1e-12));
}

// The loose-gear train with a 400-tooth input gear a (r = 0.4 m; its mesh a-b is then the
// fastest, b-side c-d runs at 400/35 x 0.019 = 0.217 m/s per rad/s): the limit is 500 rad/s.
TEST_CASE("a train's default speed sweep is clipped to its fastest mesh's limit",
          "[loader][limits][train]") {
  const std::string text = Replace(testing::kLooseGearTrainYaml, "a: {shaft: input, teeth: 21",
                                   "a: {shaft: input, teeth: 400");
  const config::LoadedGearbox loaded = config::LoadAnyGearboxFromString(text, "t.yaml");
  CHECK(loaded.train.analysis.speed_sweep.to == Approx(500.0).epsilon(1e-8));
  INFO(loaded.sweep_note);
  CHECK(Contains(loaded.sweep_note,
                 "would run meshes[0] (a-b) above the pitch-line velocity "
                 "limit of 200 m/s"));
  CHECK(Contains(loaded.sweep_note, "sweeping 500 rpm to 4774.65 rpm instead"));
}

TEST_CASE("atlas and orbits hold a speed axis of the command line to the pitch-line limit",
          "[cli][limits]") {
  TempDir dir;
  const std::string pair = std::string(GEARNVH_EXAMPLES_DIR) + "/idle_rattle.yaml";
  const std::string train = dir.Write("train.yaml", testing::kLooseGearTrainYaml).string();
  struct Case {
    std::string file, args, message;
  };
  const std::string fast = "operating.speed=600rpm:1e30rpm:2";
  for (const Case& c : std::vector<Case>{
           {pair, " atlas --x " + fast + " --y mesh.backlash=50um:100um:2",
            "--x: gives the mesh a pitch-line velocity of"},
           {pair, " atlas --y " + fast + " --x mesh.backlash=50um:100um:2",
            "--y: gives the mesh a pitch-line velocity of"},
           {pair, " orbits --sweep " + fast, "--sweep: gives the mesh a pitch-line velocity of"},
           {train, " atlas --x " + fast + " --y meshes[0].backlash=50um:100um:2",
            "--x: gives meshes[0] (a-b) a pitch-line velocity of"},
           {train, " orbits --sweep " + fast,
            "--sweep: gives meshes[0] (a-b) a pitch-line velocity of"}}) {
    const auto out = dir.path() / "out";
    const auto run = RunCommand(kExe + c.args + " --out " + out.string() + " " + c.file);
    INFO(c.args << " " << c.file << "\n" << run.err);
    CHECK(run.exit_code == 2);
    CHECK(Contains(run.err, c.message));
    CHECK(Contains(run.err, "got 1e+30 rpm"));
    CHECK(Contains(run.err, c.file == pair ? "(a speed of 70735.5 rpm here)"
                                           : "(a speed of 90945.7 rpm here)"));
    CHECK((!std::filesystem::exists(out) || std::filesystem::is_empty(out)));
  }
}

TEST_CASE("an axis the gearbox cannot vary is refused where it was named", "[cli][loader]") {
  // No excitation order: operating.excitation[0].amplitude has nothing to vary.
  std::string text = Example("idle_rattle.yaml");
  text =
      Replace(text, "  excitation:\n    - {order: 2, amplitude: 1500 rad/s^2, phase: 0 deg}", "");
  const std::string file_axis = Replace(
      text, "x: {parameter: operating.speed,  from: 600 rpm,  to: 3000 rpm",
      "x: {parameter: \"operating.excitation[0].amplitude\", from: 1 rad/s^2, to: 2 rad/s^2");
  const std::string err = LoadError(file_axis);
  INFO(err);
  CHECK(Contains(err,
                 "t.yaml:51: analysis.atlas.x.parameter: the gearbox has no "
                 "operating.excitation order to vary, got 'operating.excitation[0].amplitude'"));
  TempDir dir;
  const auto file = dir.Write("quiet.yaml", text);
  for (const std::string& args :
       {std::string(" atlas --x operating.excitation[0].amplitude=1rad/s^2:2rad/s^2:2 --y "
                    "mesh.backlash=50um:100um:2 "),
        std::string(" orbits --sweep operating.excitation[0].amplitude=1rad/s^2:2rad/s^2:2 ")}) {
    const auto run = RunCommand(kExe + args + file.string());
    INFO(args << run.err);
    CHECK(run.exit_code == 2);
    CHECK(Contains(run.err, "the gearbox has no operating.excitation order to vary"));
    CHECK(Contains(run.err, args.find("atlas") != std::string::npos ? "--x: " : "--sweep: "));
  }
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

TEST_CASE("an order finer than the segment grid is taken: it is carried exactly",
          "[cli][limits][train]") {
  // Pairs and trains carry their engine orders as an exosystem (docs/solver.md), so an order with
  // less than one segment per period (order 500 on 32 segments of a 27- and a 20-tooth mesh cycle)
  // is accepted and moves the TE; held per segment it would have been averaged away (the grid once
  // refused it).
  TempDir dir;
  const std::string pair = Example("idle_rattle.yaml");
  const std::string train = testing::kLooseGearTrainYaml;
  for (const auto& [name, text, from, to, quiet] :
       {std::tuple{"pair.yaml", pair, std::string("order: 2,"), std::string("order: 500,"),
                   std::string("amplitude: 1500 rad/s^2")},
        std::tuple{"train.yaml", train, std::string("order: 2,"), std::string("order: 500,"),
                   std::string("amplitude: 1000 rad/s^2")}}) {
    INFO(name);
    const std::string high = Replace(text, from, to);
    const auto file = dir.Write(name, high);
    const auto check = RunCommand(kExe + " check " + file.string());
    INFO(check.err);
    CHECK(check.exit_code == 0);
    const auto te_rms = [&](const std::filesystem::path& f) {
      const auto run =
          RunCommand(kExe + " simulate --json --cycles 40 --transient 0 " + f.string());
      INFO(run.err);
      REQUIRE(run.exit_code == 0);
      const auto doc = nlohmann::json::parse(run.out);
      return doc.contains("meshes") ? doc["meshes"][0]["te"]["rms"].get<double>()
                                    : doc["te"]["rms"].get<double>();
    };
    const auto silent =
        dir.Write(std::string("quiet-") + name, Replace(high, quiet, "amplitude: 0 rad/s^2"));
    // Far above rounding (~1e-12): the order moves the TE RMS by 1.3e-4 (train) and more than
    // 1e-3 (pair) when written; an order averaged away would leave it within rounding.
    CHECK(std::abs(te_rms(file) - te_rms(silent)) > 1e-6 * te_rms(silent));
  }
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
