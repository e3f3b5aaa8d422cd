// Input rules of schema gearnvh/2 (gear trains) through the loader: the operating limits on the
// train's input shaft and loads, duplicate meshes, and the messages a new user meets.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "app/three_shaft_train_yaml.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::config {
namespace {

const std::string& kBase = testing::kThreeShaftTrainYaml;
using testing::Contains;
using testing::Replace;

using testing::LoaderErrorOf;

std::string ReadExample(const std::string& name) {
  std::ifstream in(std::string(GEARNVH_EXAMPLES_DIR) + "/" + name);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST_CASE("the engine excitation limit is stated on the input shaft", "[loader][train]") {
  // Manual transmission at 600 rpm: the input turns at 62.83 rad/s, the layshaft at 21/35 of it
  // (37.70 rad/s). Order 2 at 3000 rad/s^2 fluctuates the input by 3000 / (2 x 62.83) = 23.9
  // rad/s, below its mean speed: accepted (it was refused against the layshaft's speed).
  const std::string mt =
      Replace(ReadExample("manual_transmission_idle.yaml"), "value: 800 rpm", "value: 600 rpm");
  CHECK_NOTHROW(
      LoadAnyGearboxFromString(Replace(mt, "amplitude: 1500 rad/s^2", "amplitude: 3000 rad/s^2")));
  // The limit a / (k w) <= w is a <= k w^2 = 2 x 62.83^2 = 7895.7 rad/s^2 (closed form).
  CHECK_NOTHROW(
      LoadAnyGearboxFromString(Replace(mt, "amplitude: 1500 rad/s^2", "amplitude: 7850 rad/s^2")));
  const InputError e =
      LoaderErrorOf(Replace(mt, "amplitude: 1500 rad/s^2", "amplitude: 7950 rad/s^2"));
  CHECK(e.path() == "operating.excitation[0].amplitude");
  CHECK(e.value() == "'7950 rad/s^2'");
  CHECK(e.rule().find("input shaft 'input'") != std::string::npos);
  CHECK(e.rule().find("exceed its mean speed 600 rpm") != std::string::npos);  // as written
}

TEST_CASE("the input speed must be > 0, reported as written", "[loader][train]") {
  for (const std::string speed : {"0 rpm", "-1000 rpm"}) {
    INFO(speed);
    const InputError e = LoaderErrorOf(Replace(kBase, "value: 1000 rpm", "value: " + speed));
    CHECK(e.path() == "operating.speed.value");
    CHECK(e.value() == "'" + speed + "'");
    CHECK(e.rule().find("must be > 0") != std::string::npos);
    CHECK(e.line() == 18);
  }
  // 1e-3 rpm without excitation: 60 cycles of the first mesh (23 teeth) take
  // 60 / (23 x 1e-3 / 60) s = 156522 s, above 3600 s. Named at the input speed as written.
  std::string slow = Replace(kBase, "value: 1000 rpm", "value: 1e-3 rpm");
  slow = Replace(slow, "  excitation:\n    - {order: 2, amplitude: 500 rad/s^2}\n", "");
  const InputError e = LoaderErrorOf(slow);
  CHECK(e.path() == "operating.speed.value");
  CHECK(e.value() == "'1e-3 rpm'");
  CHECK(e.rule().find("1.57e+05 s") != std::string::npos);
}

TEST_CASE("the run-length limit counts cycles of the first mesh", "[loader][train]") {
  // The sweep starts at 0.05 rpm: the first mesh (g1, 23 teeth on the input) meshes at
  // 23 x 0.05 / 60 = 0.0192 Hz, so 60 cycles last 3130 s (allowed). The second mesh (g3, 19
  // teeth at 23/41 of the input speed) would take 6758 s; it is not the one the run counts.
  const std::string text = Replace(kBase, "from: 800 rpm", "from: 0.05 rpm");
  CHECK_NOTHROW(LoadAnyGearboxFromString(text));
  const InputError e = LoaderErrorOf(Replace(kBase, "from: 800 rpm", "from: 0.04 rpm"));
  CHECK(e.path() == "analysis.speed_sweep.from");
  CHECK(e.value() == "'0.04 rpm'");
}

TEST_CASE("the tooth-load limit holds per mesh at its transmitted torque", "[loader][train]") {
  // A torque T on c passes through meshes[1] as T on g4 (pitch radius 37 mm, face 15 mm) and
  // through meshes[0] as T 19/37 on g2 (41 mm): meshes[1] reaches 20 N/um first, at
  // T = 2e7 N/m x 0.037 m x 0.015 m = 11100 N m (closed form; 1 % either side).
  CHECK_NOTHROW(LoadAnyGearboxFromString(Replace(kBase, "torque: 1 N*m", "torque: 10990 N*m")));
  const InputError e = LoaderErrorOf(Replace(kBase, "torque: 1 N*m", "torque: 11210 N*m"));
  CHECK(e.path() == "operating.loads[0].torque");
  CHECK(e.value() == "'11210 N*m'");
  CHECK(e.rule().find("meshes[1] (g3-g4)") != std::string::npos);
  CHECK(e.rule().find("20 N/um") != std::string::npos);
  const InputError huge = LoaderErrorOf(Replace(kBase, "torque: 1 N*m", "torque: 1e6 N*m"));
  CHECK(huge.path() == "operating.loads[0].torque");
}

TEST_CASE("the static torque flow follows the power through the tree", "[loader][train]") {
  const TrainSpec spec = LoadAnyGearboxFromString(kBase).train;
  const TrainTorqueFlow flow = StaticTorqueFlow(spec, AnalyseTrainTopology(spec));
  // Closed forms for 1 N m on c: T_g4 = 1, T_g2 = 19/37, T_in = (23/41)(19/37) (power balance).
  REQUIRE(flow.transmitted_torque.size() == 2);
  CHECK(flow.transmitted_torque[1] == Approx(1.0).epsilon(1e-14));
  CHECK(flow.transmitted_torque[0] == Approx(19.0 / 37.0).epsilon(1e-14));
  CHECK(flow.input_torque == Approx(23.0 / 41.0 * 19.0 / 37.0).epsilon(1e-14));
  CHECK(flow.main_load[0] == 0);
  CHECK(flow.main_load[1] == 0);
  CHECK_FALSE(flow.back_flank_loaded[0]);
  CHECK_FALSE(flow.back_flank_loaded[1]);
}

TEST_CASE("a pair of gears meshes once", "[loader][train]") {
  for (const std::string pair : {"[g3, g4]", "[g4, g3]"}) {
    INFO(pair);
    const InputError e = LoaderErrorOf(Replace(
        kBase, "  - {gears: [g3, g4], backlash: 100 um}\n",
        "  - {gears: [g3, g4], backlash: 100 um}\n  - {gears: " + pair + ", backlash: 120 um}\n"));
    CHECK(e.path() == "meshes[2].gears");
    CHECK(e.rule().find("same pair of gears as meshes[1]") != std::string::npos);
  }
}

TEST_CASE("train messages name the train's gears and the values", "[loader][train]") {
  const InputError module = LoaderErrorOf(Replace(kBase, "g4: {shaft: c, teeth: 37, module: 2 mm",
                                                  "g4: {shaft: c, teeth: 37, module: 2.5 mm"));
  CHECK(module.path() == "gears.g4.module");
  CHECK(module.rule().find("module of gears.g3") != std::string::npos);
  CHECK(module.rule().find("pinion") == std::string::npos);

  const InputError angle =
      LoaderErrorOf(Replace(kBase, "g4: {shaft: c,", "g4: {pressure_angle: 25 deg, shaft: c,"));
  CHECK(angle.path() == "gears.g4.pressure_angle");
  CHECK(angle.value() == "'25 deg'");
  CHECK(angle.rule().find("pressure angle of gears.g3 (20 deg)") != std::string::npos);

  const InputError article =
      LoaderErrorOf(Replace(kBase, "amplitude: 500 rad/s^2", "amplitude: 500 mm"));
  CHECK(article.rule().find("for an angular acceleration") != std::string::npos);
  const InputError article2 = LoaderErrorOf(Replace(kBase, "backlash: 100 um}\n  - {gears: [g3",
                                                    "backlash: 100 um, center_line_angle: x}\n  - "
                                                    "{gears: [g3"));
  CHECK(article2.rule().find("must be an angle") != std::string::npos);

  for (const std::string list : {"[g1]", "[g1, g2, g3]"}) {
    const InputError e = LoaderErrorOf(Replace(kBase, "gears: [g1, g2]", "gears: " + list));
    CHECK(e.path() == "meshes[0].gears");
    CHECK(e.value() == list);
  }

  // Standard centre distance of meshes[0]: (23 + 41) x 2 mm / 2 = 64 mm.
  const InputError cd = LoaderErrorOf(Replace(
      kBase, "[g1, g2], backlash: 100 um", "[g1, g2], backlash: 100 um, center_distance: 100 mm"));
  CHECK(cd.path() == "meshes[0].center_distance");
  CHECK(cd.value() == "'100 mm'");
  CHECK(cd.rule().find("contact ratio of -") != std::string::npos);
  CHECK(cd.rule().find("is 64 mm)") != std::string::npos);
}

TEST_CASE("a schema-1 gearbox's train names the paths the file wrote", "[loader][train]") {
  // The train TrainOf makes of a pair says meshes[0], gears.pinion.at, operating.loads[0]; an error
  // raised on it is located at, and named by, the schema-1 paths and values the file wrote.
  const std::string text = ReadExample("flexible_shafts.yaml");
  LoadedGearbox loaded = LoadAnyGearboxFromString(text, "f.yaml");
  REQUIRE(loaded.schema == 1);
  const auto located = [&](const InputError& e) {
    return std::string(LocatedIn(e, loaded.locations, "f.yaml").what());
  };
  CHECK(located(InputError("meshes[0].backlash", 0, "", "must be > 0")) ==
        "f.yaml:33: mesh.backlash: must be > 0, got '120 um'");
  CHECK(located(InputError("gears.pinion.at", 0, "", "must lie within the shaft")) ==
        "f.yaml:44: shafts.input.gear_at: must lie within the shaft, got '100 mm'");
  CHECK(located(InputError("operating.loads[0].torque", 0, "", "must be >= 0")) ==
        "f.yaml:67: operating.torque: must be >= 0, got '200 N*m'");
  CHECK(located(InputError("operating.speed.value", 0, "", "must be > 0")) ==
        "f.yaml:66: operating.speed: must be > 0, got '3000 rpm'");
  // A path the train shares with the pair is as it was; a rule's mention of a path is renamed whole
  // (meshes[0] and meshes[0].backlash, not meshes[0]x or a sentence's full stop).
  CHECK(located(InputError("gears.wheel.teeth", 0, "", "see meshes[0].")) ==
        "f.yaml:24: gears.wheel.teeth: see mesh., got '47'");
  CHECK(located(InputError("gears.wheel.teeth", 0, "",
                           "meshes[0].backlash, meshes[0]x and (meshes[0])")) ==
        "f.yaml:24: gears.wheel.teeth: mesh.backlash, meshes[0]x and (mesh), got '47'");
  // The train's own validation, on a train the pair's file could not have written, speaks of the
  // file's paths: a helix on the wheel alone breaks the rule the train states for meshes[0].
  loaded.train.gears[1].gear.helix_angle = 0.2;
  try {
    ValidateTrainSpec(loaded.train);
    FAIL("a helix on one gear of the pair passed");
  } catch (const InputError& e) {
    const std::string message = located(e);
    INFO(message);
    CHECK(message.rfind("f.yaml:24: gears.wheel.helix_angle: must equal the helix angle of", 0) ==
          0);
    CHECK(Contains(message, "the gear it meshes with in mesh"));
    CHECK_FALSE(Contains(message, "meshes[0]"));
  }
  // A schema-2 file has no aliases: its own paths stay.
  const LoadedGearbox train = LoadAnyGearboxFromString(kBase, "t.yaml");
  CHECK(std::string(LocatedIn(InputError("meshes[0].backlash", 0, "", "must be > 0"),
                              train.locations, "t.yaml")
                        .what())
            .find("meshes[0].backlash") != std::string::npos);
}

TEST_CASE("a train without a schema line is told to write one", "[loader][train]") {
  const std::string no_schema = Replace(kBase, "schema: gearnvh/2\n", "");
  const InputError e = LoaderErrorOf(no_schema);
  CHECK(e.path() == "meshes");
  CHECK(e.rule().find("write `schema: gearnvh/2`") != std::string::npos);
  // Without meshes, a shaft other than schema 1's input and output gives the train away.
  const InputError s = LoaderErrorOf(Replace(no_schema, "meshes:", "meshes_off:"));
  CHECK(s.path() == "shafts.a");
  CHECK(s.rule().find("write `schema: gearnvh/2`") != std::string::npos);
}

TEST_CASE("a directory given as input is named as one", "[loader]") {
  const std::string dir = std::filesystem::temp_directory_path().string();
  try {
    LoadAnyGearboxFile(dir);
    FAIL("read a directory");
  } catch (const InputError& e) {
    CHECK(e.rule().find("is a directory") != std::string::npos);
    CHECK(e.source() == dir);
  }
}

TEST_CASE("a drag may be viscous and act relative to a shaft", "[loader][train]") {
  // g5 idles on c: its drag as a needle bearing's, on its speed relative to c.
  const std::string loose = testing::ThreeShaftTrainWithLooseGearYaml();
  const std::string drag = "    - {on: g5, torque: 0.2 N*m}\n";
  const auto with = [&](const std::string& load) { return Replace(loose, drag, load); };
  const TrainSpec spec =
      LoadAnyGearboxFromString(
          with("    - {on: g5, torque: 0.2 N*m, viscous: 2 N*mm*s/rad, relative_to: c}\n"))
          .train;
  REQUIRE(spec.operating.loads.size() == 2);
  CHECK(spec.operating.loads[1].torque == 0.2);
  CHECK(spec.operating.loads[1].viscous == Approx(2e-3).epsilon(1e-15));
  CHECK(spec.operating.loads[1].viscous_unit.symbol == "N mm s/rad");
  CHECK(spec.operating.loads[1].viscous_unit.per_si == 1e3);
  CHECK(spec.operating.loads[1].relative_to == "c");
  // Per degree: 1 N m s/deg = 180 / pi N m s/rad.
  CHECK(LoadAnyGearboxFromString(with("    - {on: g5, viscous: 1 N*m*s/deg}\n"))
            .train.operating.loads[1]
            .viscous == Approx(180.0 / std::numbers::pi).epsilon(1e-15));
  // Viscous alone: the torque defaults to 0.
  const TrainSpec viscous =
      LoadAnyGearboxFromString(with("    - {on: g5, viscous: 1e-3 N*m*s/rad}\n")).train;
  CHECK(viscous.operating.loads[1].torque == 0.0);
  CHECK(viscous.operating.loads[1].relative_to.empty());
  // A load without either is still refused at its torque.
  CHECK(LoaderErrorOf(with("    - {on: g5}\n")).path() == "operating.loads[1].torque");

  const InputError unit = LoaderErrorOf(with("    - {on: g5, viscous: 1e-3 N*m}\n"));
  CHECK(unit.path() == "operating.loads[1].viscous");
  CHECK(unit.rule().find("rotational damping") != std::string::npos);
  const InputError large = LoaderErrorOf(with("    - {on: g5, viscous: 5000 N*m*s/rad}\n"));
  CHECK(large.path() == "operating.loads[1].viscous");
  CHECK(large.rule().find("must be in [0, 1000] N m s/rad") != std::string::npos);
  const InputError negative = LoaderErrorOf(with("    - {on: g5, viscous: -1 N*m*s/rad}\n"));
  CHECK(negative.path() == "operating.loads[1].viscous");
  const InputError unknown =
      LoaderErrorOf(with("    - {on: g5, torque: 0.2 N*m, relative_to: housing}\n"));
  CHECK(unknown.path() == "operating.loads[1].relative_to");
  CHECK(unknown.rule().find("must name a shaft") != std::string::npos);
  CHECK(unknown.rule().find("the file's shafts: a, b, c") != std::string::npos);
  const InputError empty =
      LoaderErrorOf(with("    - {on: g5, torque: 0.2 N*m, relative_to: \"\"}\n"));
  CHECK(empty.path() == "operating.loads[1].relative_to");
  CHECK(empty.rule().find("leave the key out") != std::string::npos);
  CHECK(LoaderErrorOf(with("    - {on: g5, relative_to: c}\n")).rule().find("viscous") !=
        std::string::npos);
  const InputError itself =
      LoaderErrorOf(with("    - {on: g4, torque: 0.2 N*m, relative_to: c}\n"));
  CHECK(itself.path() == "operating.loads[1].relative_to");
  CHECK(itself.rule().find("relative to itself") != std::string::npos);
}

TEST_CASE("a train without gears or meshes is told it needs a mesh", "[loader][train]") {
  // Shafts joined only by a coupling: the first missing key says what a gear train needs.
  const std::string couplings_only =
      "schema: gearnvh/2\nname: shafts only\nshafts:\n  a: {inertia: 0.1 kg*m^2}\n"
      "  b: {inertia: 0.2 kg*m^2}\ncouplings:\n  k: {between: [a, b], stiffness: 100}\n"
      "operating:\n  speed: {shaft: a, value: 1000 rpm}\n";
  const InputError e = testing::LoaderErrorOf(couplings_only);
  CHECK(e.path() == "gears");
  CHECK(e.rule().find("at least one mesh between two gears") != std::string::npos);
}

TEST_CASE("an excitation order above 1000 is refused as a slip", "[loader][train]") {
  // An order of 1e6 at 1000 rpm (16.7 MHz) was accepted and ran 10 s for 5 cycles.
  const InputError e = testing::LoaderErrorOf(testing::ReplaceFirst(
      testing::kThreeShaftTrainYaml, "{order: 2, amplitude", "{order: 1e6, amplitude"));
  CHECK(e.path() == "operating.excitation[0].order");
  CHECK(e.rule().find("must be <= 1000") != std::string::npos);
  CHECK_NOTHROW(LoadAnyGearboxFromString(testing::ReplaceFirst(
      testing::kThreeShaftTrainYaml, "{order: 2, amplitude", "{order: 1000, amplitude")));
}

TEST_CASE("a part name that is empty or holds a comma or a double quote is refused at its key",
          "[loader][train]") {
  // Names head CSV columns (trajectory.csv: "<coupling>.twist_rad"); a comma split the header.
  const std::string& base = testing::kThreeShaftTrainYaml;
  const InputError shaft = testing::LoaderErrorOf(
      testing::ReplaceFirst(testing::ReplaceFirst(base, "  c: {inertia", "  \"c,1\": {inertia"),
                            "{on: c,", "{on: \"c,1\","));
  CHECK(shaft.path() == "shafts.c,1");
  CHECK(shaft.rule().find("must not contain ','") != std::string::npos);
  CHECK(shaft.rule().find("CSV") != std::string::npos);
  const InputError gear =
      testing::LoaderErrorOf(testing::ReplaceFirst(base, "  g4: {", "  'g\"4': {"));
  CHECK(gear.path() == "gears.g\"4");
  CHECK(gear.rule().find("must not contain '\"'") != std::string::npos);
  const InputError coupling = testing::LoaderErrorOf(testing::ReplaceFirst(
      base, "operating:\n",
      "couplings:\n  \"k,1\": {between: [c, a], stiffness: 500}\noperating:\n"));
  CHECK(coupling.path() == "couplings.k,1");
  const InputError empty =
      testing::LoaderErrorOf(testing::ReplaceFirst(base, "  c: {inertia", "  \"\": {inertia"));
  CHECK(empty.path() == "shafts.");
  CHECK(empty.rule().find("must not be empty") != std::string::npos);
  // Two meshes whose gear names join to one mesh name ('a-b' + 'c', 'a' + 'b-c') are refused at
  // the second.
  std::string joined = testing::ReplaceFirst(base, "  g1: {", "  g-1: {");
  joined = testing::ReplaceFirst(joined, "  g3: {", "  g: {");
  joined = testing::ReplaceFirst(joined, "  g4: {", "  1-g2: {");
  joined = testing::ReplaceFirst(joined, "[g1, g2]", "[g-1, g2]");
  joined = testing::ReplaceFirst(joined, "[g3, g4]", "[g, 1-g2]");
  const InputError same = testing::LoaderErrorOf(joined);
  CHECK(same.path() == "meshes[1].gears");
  CHECK(same.rule().find("gives the mesh name 'g-1-g2', as meshes[0]") != std::string::npos);
  // Other punctuation and spaces stay allowed (quoted CSV fields are not needed for them).
  CHECK_NOTHROW(LoadAnyGearboxFromString(testing::ReplaceFirst(
      testing::ReplaceFirst(base, "  g4: {", "  'g 4/x': {"), "[g3, g4]", "[g3, 'g 4/x']")));
}

TEST_CASE("a coupling joins two shafts with a stiffness and a damping, in the units written",
          "[loader][train]") {
  // A flywheel behind shaft a, through a clutch damper; the speed given on the flywheel.
  const auto with = [](const std::string& coupling) {
    std::string text = testing::ReplaceFirst(testing::kThreeShaftTrainYaml,
                                             "  c: {inertia: 1e-3 kg*m^2}\n",
                                             "  c: {inertia: 1e-3 kg*m^2}\n"
                                             "  flywheel: {inertia: 0.12 kg*m^2}\n");
    text = testing::ReplaceFirst(text, "operating:\n", "couplings:\n" + coupling + "operating:\n");
    return testing::ReplaceFirst(text, "{shaft: a, value: 1000 rpm}",
                                 "{shaft: flywheel, value: 1000 rpm}");
  };
  const TrainSpec spec =
      LoadAnyGearboxFromString(with("  clutch_damper: {between: [flywheel, a], stiffness: 9 "
                                    "N*m/deg, damping: 50 N*mm*s/rad}\n"))
          .train;
  REQUIRE(spec.couplings.size() == 1);
  const TrainCoupling& c = spec.couplings[0];
  CHECK(c.name == "clutch_damper");
  CHECK(c.shaft_a == "flywheel");
  CHECK(c.shaft_b == "a");
  CHECK(c.stiffness == Approx(9.0 * 180.0 / std::numbers::pi).epsilon(1e-15));
  CHECK(c.stiffness_unit.symbol == "N m/deg");
  CHECK(c.damping == Approx(0.05).epsilon(1e-15));
  CHECK(c.damping_unit.symbol == "N mm s/rad");
  // Damping defaults to 0.
  CHECK(LoadAnyGearboxFromString(with("  k: {between: [flywheel, a], stiffness: 500}\n"))
            .train.couplings[0]
            .damping == 0.0);
  // Stages: the first's stiffness is the coupling's, each `to` starts the next stage, in the
  // units written.
  const TrainCoupling staged =
      LoadAnyGearboxFromString(
          with("  k: {between: [flywheel, a], stages: [{to: 1.5 deg, stiffness: 0.4 N*m/deg}, "
               "{to: 8 deg, stiffness: 9 N*m/deg}, {stiffness: 60 N*m/deg}]}\n"))
          .train.couplings[0];
  const double deg = std::numbers::pi / 180.0;
  CHECK(staged.stiffness == Approx(0.4 / deg).epsilon(1e-15));
  REQUIRE(staged.stages.size() == 2);
  CHECK(staged.stages[0].from == Approx(1.5 * deg).epsilon(1e-15));
  CHECK(staged.stages[0].stiffness == Approx(9.0 / deg).epsilon(1e-15));
  CHECK(staged.stages[1].from == Approx(8.0 * deg).epsilon(1e-15));
  CHECK(staged.stages[1].stiffness == Approx(60.0 / deg).epsilon(1e-15));
  CHECK(staged.angle_unit.symbol == "deg");
  // Malformed stages are refused at their key, saying why.
  const InputError lone = testing::LoaderErrorOf(
      with("  k: {between: [flywheel, a], stages: [{to: 1.5 deg, stiffness: 0.4 N*m/deg}]}\n"));
  CHECK(lone.path() == "couplings.k.stages");
  CHECK(lone.rule().find("at least two stages") != std::string::npos);
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stages: [{to: 1 deg, "
                                    "stiffness: 5}, {to: 2 deg, stiffness: 50}]}\n"))
            .path() == "couplings.k.stages[1].to");
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stages: [{stiffness: 5}, "
                                    "{stiffness: 50}]}\n"))
            .path() == "couplings.k.stages[0].to");
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stiffness: 5, stages: [{to: 1 "
                                    "deg, stiffness: 5}, {stiffness: 50}]}\n"))
            .path() == "couplings.k.stiffness");
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stages: [{to: 1 N*m, "
                                    "stiffness: 5}, {stiffness: 50}]}\n"))
            .path() == "couplings.k.stages[0].to");
  // The model's stage rules at the file's path: a softer stage after a stiffer one.
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stages: [{to: 1 deg, "
                                    "stiffness: 50}, {stiffness: 5}]}\n"))
            .path() == "couplings.k.stages[1].stiffness");
  // What is not built yet is refused at its key, saying so.
  const InputError hysteresis = testing::LoaderErrorOf(
      with("  k: {between: [flywheel, a], stiffness: 500, hysteresis: 1.5 N*m}\n"));
  CHECK(hysteresis.path() == "couplings.k.hysteresis");
  CHECK(hysteresis.rule().find("not built yet") != std::string::npos);
  const InputError one = testing::LoaderErrorOf(with("  k: {between: [flywheel], stiffness: 500}\n"));
  CHECK(one.path() == "couplings.k.between");
  CHECK(one.rule().find("two shaft names") != std::string::npos);
  const InputError unit =
      testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stiffness: 500 N*m}\n"));
  CHECK(unit.path() == "couplings.k.stiffness");
  CHECK(unit.rule().find("rotational stiffness") != std::string::npos);
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a]}\n")).path() ==
        "couplings.k.stiffness");
  CHECK(testing::LoaderErrorOf(with("  k: {between: [flywheel, a], stifness: 500}\n")).path() ==
        "couplings.k.stifness");
  // The model's rules, at the file's line: a gear is not a shaft.
  const InputError gear =
      testing::LoaderErrorOf(with("  k: {between: [flywheel, g1], stiffness: 500}\n"));
  CHECK(gear.path() == "couplings.k.between");
  CHECK(gear.line() > 0);
}

TEST_CASE("an engine order may be a torque on any shaft", "[loader][train]") {
  const std::string order = "    - {order: 2, amplitude: 500 rad/s^2}\n";
  const auto with = [&](const std::string& line) {
    return testing::ReplaceFirst(testing::kThreeShaftTrainYaml, order, line);
  };
  const ExcitationOrder e =
      LoadAnyGearboxFromString(
          with("    - {kind: torque, on: b, order: 1.5, amplitude: 3 N*m, phase: 90 deg}\n"))
          .train.operating.excitation.at(0);
  CHECK(e.kind == ExcitationKind::kTorque);
  CHECK(e.on == "b");
  CHECK(e.order == 1.5);
  CHECK(e.amplitude == 3.0);
  CHECK(e.phase == Approx(std::numbers::pi / 2.0).epsilon(1e-15));
  // The written default: an acceleration of the input shaft.
  const ExcitationOrder plain =
      LoadAnyGearboxFromString(testing::kThreeShaftTrainYaml).train.operating.excitation.at(0);
  CHECK(plain.kind == ExcitationKind::kAcceleration);
  CHECK(plain.on.empty());
  // A torque's amplitude is a torque; an acceleration's is not.
  const InputError unit =
      testing::LoaderErrorOf(with("    - {kind: torque, order: 2, amplitude: 500 rad/s^2}\n"));
  CHECK(unit.path() == "operating.excitation[0].amplitude");
  CHECK(unit.rule().find("torque") != std::string::npos);
  const InputError motion =
      testing::LoaderErrorOf(with("    - {kind: motion, order: 2, amplitude: 25 rpm}\n"));
  CHECK(motion.path() == "operating.excitation[0].kind");
  CHECK(motion.rule().find("not built yet") != std::string::npos);
  const InputError shaft =
      testing::LoaderErrorOf(with("    - {kind: torque, on: g2, order: 2, amplitude: 3 N*m}\n"));
  CHECK(shaft.path() == "operating.excitation[0].on");
  CHECK(shaft.rule().find("the file's shafts: a, b, c") != std::string::npos);
  CHECK(shaft.line() > 0);
}

}  // namespace
}  // namespace gearnvh::config
