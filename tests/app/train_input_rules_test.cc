// Input rules a new-user trial of gear trains found missing or inconsistent (issue 20 review):
// absurd inertias, atlas parameters of a train, the segment grid, the speed and excitation-order
// limits, and messages that echo the values as written with their line.
#include <catch2/catch.hpp>
#include <string>

#include "app/three_shaft_train_yaml.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::config {
namespace {

const std::string kLooseGearTrain = testing::ThreeShaftTrainWithLooseGearYaml();
using testing::Replace;

using testing::LoaderErrorOf;

TEST_CASE("a body inertia above 1e9 kg m^2 is refused as written", "[loader][train]") {
  // 1e300 kg m^2 once made `check` report a NaN critical speed (an internal error).
  CHECK_NOTHROW(LoadAnyGearboxFromString(
      Replace(kLooseGearTrain, "b: {inertia: 3e-3 kg*m^2}", "b: {inertia: 1e9 kg*m^2}")));
  for (const std::string v : {"1e300 kg*m^2", "2e9 kg*m^2", "2e15 kg*mm^2"}) {
    INFO(v);
    const InputError e =
        LoaderErrorOf(Replace(kLooseGearTrain, "b: {inertia: 3e-3 kg*m^2}", "b: {inertia: " + v + "}"));
    CHECK(e.path() == "shafts.b.inertia");
    CHECK(e.value() == "'" + v + "'");
    CHECK(e.line() == 7);
    CHECK(e.rule().find("must be <= 1e+09 kg m^2") != std::string::npos);
  }
  // A gear's own inertia override follows the same rule.
  const InputError g =
      LoaderErrorOf(Replace(kLooseGearTrain, "g5: {shaft: c, mounting: loose,",
                            "g5: {shaft: c, inertia: 1e300 kg*m^2, mounting: loose,"));
  CHECK(g.path() == "gears.g5.inertia");
  CHECK(g.value() == "'1e300 kg*m^2'");
}

TEST_CASE("a misspelt key of a shaft gets its did-you-mean in either form", "[loader][train]") {
  // A misspelt `segments` once made the shaft rigid, and the other elastic keys were then called
  // unknown with the rigid keys as the only choices.
  const std::string elastic =
      Replace(kLooseGearTrain, "b: {inertia: 3e-3 kg*m^2}",
              "b: {material: steel, segmnts: [{length: 100 mm, outer_diameter: 30 mm}],\n"
              "     bearings: [{at: 10 mm, radial_stiffness: 1e8 N/m}]}");
  const InputError typo = LoaderErrorOf(elastic);
  CHECK(typo.path() == "shafts.b.segmnts");
  CHECK(typo.rule() == "unknown key (did you mean 'segments'?)");
  CHECK(typo.line() == 7);
  // An elastic key on a shaft without segments says which form it belongs to.
  const InputError rigid = LoaderErrorOf(
      Replace(kLooseGearTrain, "b: {inertia: 3e-3 kg*m^2}", "b: {inertia: 3e-3 kg*m^2, material: steel}"));
  CHECK(rigid.path() == "shafts.b.material");
  CHECK(rigid.rule().find("belongs to an elastic shaft, which needs segments:") !=
        std::string::npos);
  // The rigid form's own keys keep theirs.
  const InputError inertia =
      LoaderErrorOf(Replace(kLooseGearTrain, "b: {inertia: 3e-3 kg*m^2}", "b: {inertai: 3e-3 kg*m^2}"));
  CHECK(inertia.rule() == "unknown key (did you mean 'inertia'?)");
}

TEST_CASE("analysis.atlas of a train names train parameters", "[loader][train]") {
  const std::string atlas =
      "  atlas:\n"
      "    x: {parameter: 'meshes[2].backlash', from: 50 um, to: 150 um, points: 3}\n"
      "    y: {parameter: 'operating.loads[1].torque', from: 0.05 N*m, to: 0.5 N*m, points: 2, "
      "scale: log}\n";
  const std::string text = kLooseGearTrain + atlas;
  const LoadedGearbox loaded = LoadAnyGearboxFromString(text);
  REQUIRE(loaded.train.analysis.atlas_x);
  REQUIRE(loaded.train.analysis.atlas_y);
  CHECK(loaded.train.analysis.atlas_x->parameter == "meshes[2].backlash");
  // Units as the train parameter's dimension: 50 um = 5e-5 m, 0.5 N*m (exact conversions, 1e-15).
  CHECK(loaded.train.analysis.atlas_x->range.from == Approx(5e-5).epsilon(1e-15));
  CHECK(loaded.train.analysis.atlas_y->range.to == Approx(0.5).epsilon(1e-15));
  CHECK(loaded.train.analysis.atlas_y->range.scale == AxisScale::kLog);

  // A schema-1 name is refused with the train's forms, at its line (analysis.atlas.x is line 32).
  const InputError pair = LoaderErrorOf(Replace(text, "'meshes[2].backlash'", "mesh.backlash"));
  CHECK(pair.path() == "analysis.atlas.x.parameter");
  CHECK(pair.line() == 32);
  CHECK(pair.value() == "'mesh.backlash'");
  CHECK(pair.rule().find("meshes[i].backlash") != std::string::npos);
  // An index beyond the file's list names what the list has.
  const InputError index =
      LoaderErrorOf(Replace(text, "'operating.loads[1].torque'", "'operating.loads[2].torque'"));
  CHECK(index.path() == "analysis.atlas.y.parameter");
  CHECK(index.line() == 33);
  CHECK(index.value() == "'operating.loads[2].torque'");
  CHECK(index.rule().find("0: on c, 1: on g5") != std::string::npos);
  // A value in the wrong dimension for the parameter.
  const InputError unit = LoaderErrorOf(Replace(text, "from: 50 um", "from: 50 rpm"));
  CHECK(unit.path() == "analysis.atlas.x.from");
}

}  // namespace
}  // namespace gearnvh::config
