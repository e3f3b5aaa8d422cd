// Schema gearnvh/2 (gear trains): the document reader and the loader of either schema.
#include <yaml-cpp/yaml.h>

#include <tuple>
#include <utility>

#include "gearbox_loader.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/train_spec.h"
#include "spec_sections.h"
#include "train_parameters.h"
#include "yaml_reader.h"

namespace gearnvh::config {
namespace {

// A list as written in flow style ("[g1, g2, g3]"), other nodes as Describe says.
std::string ListText(const YAML::Node& n) {
  if (!n.IsSequence()) return Describe(n);
  std::string s = "[";
  for (size_t i = 0; i < n.size(); ++i) {
    s += (i == 0 ? "" : ", ") + (n[i].IsScalar() ? n[i].Scalar() : Describe(n[i]));
  }
  return s + "]";
}

// `key`: a list of two names of `what` ("gears: [g1, g2]"), each without control characters.
std::pair<std::string, std::string> ReadNamePair(Reader& r, const YAML::Node& map,
                                                 const std::string& path, const std::string& key,
                                                 const std::string& what) {
  const std::string p = Join(path, key);
  const YAML::Node pair = r.Child(map, path, key, true);
  if (!pair.IsSequence() || pair.size() != 2 || !pair[0].IsScalar() || !pair[1].IsScalar()) {
    r.Fail(p, pair, ListText(pair),
           pair.IsSequence()
               ? "must be a list of two " + what + " names, not " + std::to_string(pair.size())
               : "must be a list of two " + what + " names");
  }
  r.Remember(p, pair, "");
  for (size_t i = 0; i < 2; ++i) {
    r.RequireNoControlCharacters(p + "[" + std::to_string(i) + "]", pair[i], pair[i].Scalar());
  }
  return {pair[0].Scalar(), pair[1].Scalar()};
}

// A coupling's `stages`: [{to, stiffness}, ..., {stiffness}], each but the last ending at `to`;
// the first stage's stiffness becomes the coupling's, the others TrainCouplingStages from the
// stage before's `to` (their order and values are the model's rules).
void ReadCouplingStages(Reader& r, const YAML::Node& map, const std::string& p, TrainCoupling& c) {
  const YAML::Node list = map["stages"];
  const std::string path = Join(p, "stages");
  if (!list.IsSequence() || list.size() < 2) {
    r.Fail(path, list,
           list.IsSequence() ? "a list of " + std::to_string(list.size()) + " stage" +
                                   (list.size() == 1 ? "" : "s")
                             : Describe(list),
           "must be a list of at least two stages ({to, stiffness} for each but the last, "
           "{stiffness} for the last, which holds beyond the last `to`); a one-stage coupling "
           "gives `stiffness`");
  }
  size_t index = 0;
  r.ForEachItem(map, p, "stages", true, [&](const YAML::Node& item, const std::string& q) {
    if (!item.IsMap()) r.Fail(q, item, Describe(item), "must be a mapping {to, stiffness}");
    r.ExpectMap(item, q, {"to", "stiffness"});
    const double k = r.Quantity(item, q, "stiffness", Dimension::kRotationalStiffness);
    if (index == 0) {
      c.stiffness = k;
      c.stiffness_unit =
          DisplayUnitOf(r.Find(q + ".stiffness").raw, Dimension::kRotationalStiffness);
    } else {
      c.stages.back().stiffness = k;
    }
    if (++index == list.size()) {
      if (item["to"].IsDefined()) {
        r.Fail(Join(q, "to"), item["to"], item["to"].Scalar(),
               "must be left out: the last stage holds beyond the stage before's `to`");
      }
      return;
    }
    const double to = r.Quantity(item, q, "to", Dimension::kAngle);
    c.angle_unit = DisplayUnitOf(r.Find(q + ".to").raw, Dimension::kAngle);
    c.stages.push_back({to, 0.0});
  });
}

// couplings: {name: {between: [shaft, shaft], stiffness | stages, damping}}: spring-dampers, linear
// or in stages.
std::vector<TrainCoupling> ReadCouplings(Reader& r, const YAML::Node& root) {
  std::vector<TrainCoupling> out;
  const YAML::Node couplings = r.Child(root, "", "couplings", false);
  if (!couplings) return out;
  r.ExpectMap(couplings, "couplings", {});
  for (const auto& kv : couplings) {
    TrainCoupling c;
    c.name = kv.first.Scalar();
    const std::string p = "couplings." + c.name;
    r.RequirePartName(p, kv.first, c.name);
    if (!kv.second.IsMap()) r.Fail(p, kv.second, Describe(kv.second), "must be a mapping");
    r.ExpectMap(kv.second, p, {"between", "stiffness", "damping", "stages", "hysteresis"});
    if (kv.second["hysteresis"].IsDefined()) {
      r.Fail(Join(p, "hysteresis"), kv.second["hysteresis"], "hysteresis",
             "is not built yet: a coupling is a spring-damper, linear or in `stages`, with "
             "viscous `damping`; hysteresis (stick-slip friction) is planned (docs/gear-trains.md, "
             "\"Couplings\")");
    }
    std::tie(c.shaft_a, c.shaft_b) = ReadNamePair(r, kv.second, p, "between", "shaft");
    const bool staged = kv.second["stages"].IsDefined();
    if (staged && kv.second["stiffness"].IsDefined()) {
      r.Fail(Join(p, "stiffness"), kv.second["stiffness"], kv.second["stiffness"].Scalar(),
             "must be left out with `stages` (the first stage's stiffness is the coupling's "
             "around zero twist)");
    }
    if (staged) {
      ReadCouplingStages(r, kv.second, p, c);
    } else {
      c.stiffness = r.Quantity(kv.second, p, "stiffness", Dimension::kRotationalStiffness);
      c.stiffness_unit =
          DisplayUnitOf(r.Find(p + ".stiffness").raw, Dimension::kRotationalStiffness);
    }
    c.damping = r.Quantity(kv.second, p, "damping", Dimension::kRotationalDamping, 0.0);
    if (kv.second["damping"].IsDefined()) {
      c.damping_unit = DisplayUnitOf(r.Find(p + ".damping").raw, Dimension::kRotationalDamping);
    }
    out.push_back(c);
  }
  return out;
}

// Schema gearnvh/2: shafts, gears and meshes by name.
TrainSpec ReadTrainDocument(Reader& r, const YAML::Node& root) {
  r.ExpectMap(
      root, "",
      {"schema", "name", "materials", "shafts", "gears", "meshes", "couplings", "operating",
       "analysis"});
  TrainSpec spec;
  spec.name = r.String(root, "", "name");
  for (const char* key : {"gears", "meshes"}) {
    if (!root[key].IsDefined()) {
      r.Fail(key, root, "",
             "required key is missing: a gear train has at least one mesh between two gears "
             "(shafts joined only by couplings are not a gearbox)");
    }
  }
  spec.materials = ReadMaterials(r, root);

  const YAML::Node shafts = r.Child(root, "", "shafts", true);
  r.ExpectMap(shafts, "shafts", {});
  for (const auto& kv : shafts) {
    TrainShaft shaft;
    shaft.name = kv.first.Scalar();
    const std::string p = "shafts." + shaft.name;
    r.RequirePartName(p, kv.first, shaft.name);
    if (!kv.second.IsMap()) r.Fail(p, kv.second, Describe(kv.second), "must be a mapping");
    if (kv.second["segments"].IsDefined()) {
      shaft.elastic = ReadShaft(r, kv.second, p, spec.materials, 2);
    } else {
      // Rigid, unless `segments` is misspelt: the keys of both forms are known here (the rigid
      // ones first, so that a tie suggests them), so the misspelling gets its did-you-mean.
      std::vector<std::string> either = {"inertia", "bearings"};
      for (const std::string& key : ElasticShaftKeys(2)) {
        if (key != "bearings") either.push_back(key);
      }
      r.ExpectMap(kv.second, p, either);
      for (const std::string& key : ElasticShaftKeys(2)) {
        if (key == "bearings" || key == "fixed" || !kv.second[key].IsDefined()) continue;
        r.Fail(Join(p, key), kv.second[key], key,
               "belongs to an elastic shaft, which needs segments: (a rigid shaft has inertia "
               "and bearings)");
      }
      shaft.inertia = r.Quantity(kv.second, p, "inertia", Dimension::kInertia);
      shaft.bearings = ReadBearings(r, kv.second, p, false);
    }
    shaft.fixed = r.Boolean(kv.second, p, "fixed", false);
    spec.shafts.push_back(shaft);
  }
  if (spec.shafts.empty()) r.Fail("shafts", shafts, "{}", "needs at least one shaft");

  const YAML::Node gears = r.Child(root, "", "gears", true);
  r.ExpectMap(gears, "gears", {});
  for (const auto& kv : gears) {
    TrainGear gear;
    gear.name = kv.first.Scalar();
    const std::string p = "gears." + gear.name;
    r.RequirePartName(p, kv.first, gear.name);
    gear.gear = ReadGear(r, kv.second, p, spec.materials, {"shaft", "at", "mounting"});
    gear.shaft = r.String(kv.second, p, "shaft");
    gear.at = r.OptionalQuantity(kv.second, p, "at", Dimension::kLength);
    const std::string mounting = r.String(kv.second, p, "mounting", std::string("fixed"));
    if (mounting != "fixed" && mounting != "loose") {
      r.Fail(Join(p, "mounting"), kv.second["mounting"], "'" + mounting + "'",
             "must be fixed or loose");
    }
    gear.mounting = mounting == "fixed" ? Mounting::kFixed : Mounting::kLoose;
    spec.gears.push_back(gear);
  }

  r.ForEachItem(root, "", "meshes", true, [&](const YAML::Node& item, const std::string& p) {
    TrainMesh mesh;
    mesh.mesh = ReadMesh(r, item, p, {"gears", "center_line_angle", "effective_mass"});
    mesh.center_line_angle = r.Quantity(item, p, "center_line_angle", Dimension::kAngle, 0.0);
    const std::string mass = r.String(item, p, "effective_mass", std::string("bodies"));
    if (mass != "bodies" && mass != "gears") {
      r.Fail(Join(p, "effective_mass"), item["effective_mass"], "'" + mass + "'",
             "must be bodies or gears");
    }
    mesh.effective_mass = mass == "gears" ? MeshEffectiveMass::kGears : MeshEffectiveMass::kBodies;
    std::tie(mesh.gear_a, mesh.gear_b) = ReadNamePair(r, item, p, "gears", "gear");
    spec.meshes.push_back(mesh);
  });

  spec.couplings = ReadCouplings(r, root);

  const YAML::Node op = r.Child(root, "", "operating", true);
  r.ExpectMap(op, "operating", {"speed", "loads", "excitation"});
  const YAML::Node speed = r.Child(op, "operating", "speed", true);
  r.ExpectMap(speed, "operating.speed", {"shaft", "value"});
  spec.operating.input_shaft = r.String(speed, "operating.speed", "shaft");
  spec.operating.speed = r.Quantity(speed, "operating.speed", "value", Dimension::kAngularSpeed);
  spec.operating.speed_unit =
      DisplayUnitOf(r.Find("operating.speed.value").raw, Dimension::kAngularSpeed);
  r.ForEachItem(op, "operating", "loads", false, [&](const YAML::Node& item, const std::string& p) {
    r.ExpectMap(item, p, {"on", "torque", "viscous", "relative_to"});
    TrainLoad load;
    load.on = r.String(item, p, "on");
    // A drag may be viscous alone; a load is a torque otherwise.
    load.viscous = r.Quantity(item, p, "viscous", Dimension::kRotationalDamping, 0.0);
    const bool viscous = item["viscous"].IsDefined();
    if (!viscous && !item["torque"].IsDefined()) {
      r.Fail(p + ".torque", item, "",
             "required key is missing (a load is a torque, a viscous drag "
             "`viscous`, or both)");
    }
    load.torque = r.Quantity(item, p, "torque", Dimension::kTorque, 0.0);
    if (item["torque"].IsDefined()) {
      load.torque_unit = DisplayUnitOf(r.Find(p + ".torque").raw, Dimension::kTorque);
    }
    if (viscous) {
      load.viscous_unit = DisplayUnitOf(r.Find(p + ".viscous").raw, Dimension::kRotationalDamping);
    }
    load.relative_to = r.String(item, p, "relative_to", "");
    if (item["relative_to"].IsDefined() && load.relative_to.empty()) {
      r.Fail(p + ".relative_to", item["relative_to"], "''",
             "must name a shaft (leave the key out for a drag on the absolute speed)");
    }
    spec.operating.loads.push_back(load);
  });
  spec.operating.excitation = ReadExcitation(r, op, 2);
  spec.analysis = ReadAnalysis(r, root, 2);
  return spec;
}

// analysis.atlas names entries of the file's lists (operating.loads[i], meshes[i] ...): an index
// beyond the list is refused here, at the axis's line, rather than when an atlas starts.
void ValidateTrainAtlasAxes(const TrainSpec& spec) {
  const AnalysisSpec& an = spec.analysis;
  for (const auto& [axis, path] : {std::pair{&an.atlas_x, "analysis.atlas.x.parameter"},
                                   std::pair{&an.atlas_y, "analysis.atlas.y.parameter"}}) {
    if (!*axis) continue;
    TrainSpec variant = spec;
    SetTrainParameter(variant, (*axis)->parameter, (*axis)->range.from, path);
  }
  if (an.atlas_x && an.atlas_y && an.atlas_x->parameter == an.atlas_y->parameter) {
    throw InputError("analysis.atlas.y.parameter", 0, an.atlas_y->parameter,
                     "must differ from the x parameter");
  }
}

// The train TrainOf makes of a schema-1 gearbox names its paths as schema 2 does; its errors
// name the paths the file wrote (the inverse of the renaming ValidateTrainSpec applies to the
// pair rules it restates).
void AliasSchemaOnePaths(SourceLocations& locations) {
  locations.Alias("meshes[0]", "mesh");
  locations.Alias("gears.pinion.at", "shafts.input.gear_at");
  locations.Alias("gears.wheel.at", "shafts.output.gear_at");
  // The one load is the file's operating.torque (on the wheel, or the pinion's in its ratio).
  locations.Alias("operating.loads[0]", "operating.torque");
  locations.Alias("operating.loads[0].torque", "operating.torque");
  locations.Alias("operating.loads[0].on", "operating.torque_on");
  locations.Alias("operating.speed.value", "operating.speed");
  locations.Alias("operating.speed.shaft", "operating.speed");
}

}  // namespace

LoadedGearbox LoadAnyGearboxFromString(const std::string& text, const std::string& source) {
  const YAML::Node root = ParseYaml(text, source);
  LoadedGearbox out;
  {
    Reader probe;
    try {
      out.schema = SchemaOf(probe, root);
    } catch (const InputError& e) {
      throw e.WithSource(source);
    }
  }
  if (out.schema == 1) {
    out.pair = LoadPairFromString(text, source, out.locations, out.sweep_note);
    out.train = TrainOf(*out.pair);
    AliasSchemaOnePaths(out.locations);
    return out;
  }
  out.train = ReadAndValidate(
      root, source, ReadTrainDocument,
      [&out](TrainSpec& spec) {
        ValidateTrainSpec(spec);
        ValidateTrainAtlasAxes(spec);
        const FastestMesh fastest = FastestPitchLine(spec, AnalyseTrainTopology(spec));
        out.sweep_note =
            HoldSpeedsToPitchLineLimit(spec.analysis, out.locations, spec.operating.speed_unit,
                                       fastest.velocity_per_speed, fastest.name);
      },
      out.locations);
  return out;
}

LoadedGearbox LoadAnyGearboxFile(const std::string& path) {
  return LoadAnyGearboxFromString(ReadGearboxText(path), path);
}

}  // namespace gearnvh::config
