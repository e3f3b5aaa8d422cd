#include "spec_sections.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "train_parameters.h"

namespace gearnvh::config {

namespace {

const std::vector<std::string> kGearKeys{"teeth",
                                         "module",
                                         "pressure_angle",
                                         "face_width",
                                         "bore_diameter",
                                         "material",
                                         "addendum_coefficient",
                                         "dedendum_coefficient",
                                         "profile_shift",
                                         "inertia",
                                         "mass",
                                         "tip_relief",
                                         "lead",
                                         "helix_angle",
                                         "hand",
                                         "runout",
                                         "pitch_errors"};

}  // namespace

GearSpec ReadGear(Reader& r, const YAML::Node& n, const std::string& path,
                  const std::map<std::string, Material>& materials,
                  const std::vector<std::string>& extra_keys) {
  std::vector<std::string> keys = kGearKeys;
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  r.ExpectMap(n, path, keys);
  GearSpec g;
  g.teeth = r.Integer(n, path, "teeth");
  g.module = r.Quantity(n, path, "module", Dimension::kLength);
  g.pressure_angle = r.Quantity(n, path, "pressure_angle", Dimension::kAngle, g.pressure_angle);
  g.face_width = r.Quantity(n, path, "face_width", Dimension::kLength);
  g.bore_diameter = r.Quantity(n, path, "bore_diameter", Dimension::kLength);
  g.material = r.String(n, path, "material");
  if (materials.find(g.material) == materials.end()) {
    std::vector<std::string> keys;
    keys.reserve(materials.size());
    for (const auto& kv : materials) keys.push_back(kv.first);
    std::string rule = "must name a key of materials";
    const std::string close = ClosestMatch(g.material, keys);
    if (!close.empty()) rule += " (did you mean '" + close + "'?)";
    r.Fail(Join(path, "material"), n["material"], "'" + g.material + "'", rule);
  }
  g.addendum_coefficient = r.Quantity(n, path, "addendum_coefficient", Dimension::kDimensionless,
                                      g.addendum_coefficient);
  g.dedendum_coefficient = r.Quantity(n, path, "dedendum_coefficient", Dimension::kDimensionless,
                                      g.dedendum_coefficient);
  g.profile_shift =
      r.Quantity(n, path, "profile_shift", Dimension::kDimensionless, g.profile_shift);
  g.inertia = r.OptionalQuantity(n, path, "inertia", Dimension::kInertia);
  g.mass = r.OptionalQuantity(n, path, "mass", Dimension::kMass);
  if (const YAML::Node t = r.Child(n, path, "tip_relief", false); t.IsDefined()) {
    const std::string p = Join(path, "tip_relief");
    r.ExpectMap(t, p, {"amount", "length"});
    g.tip_relief = TipRelief{r.Quantity(t, p, "amount", Dimension::kLength),
                             r.Quantity(t, p, "length", Dimension::kLength)};
  }
  if (const YAML::Node t = r.Child(n, path, "lead", false); t.IsDefined()) {
    const std::string p = Join(path, "lead");
    r.ExpectMap(t, p, {"crowning", "end_relief", "slope"});
    LeadModification lead;
    lead.crowning = r.Quantity(t, p, "crowning", Dimension::kLength, 0.0);
    if (const YAML::Node e = r.Child(t, p, "end_relief", false); e.IsDefined()) {
      const std::string pe = Join(p, "end_relief");
      r.ExpectMap(e, pe, {"amount", "length"});
      lead.end_relief_amount = r.Quantity(e, pe, "amount", Dimension::kLength);
      lead.end_relief_length = r.Quantity(e, pe, "length", Dimension::kLength);
    }
    lead.slope = r.Quantity(t, p, "slope", Dimension::kLength, 0.0);
    g.lead = lead;
  }
  g.helix_angle = r.Quantity(n, path, "helix_angle", Dimension::kAngle, 0.0);
  if (const YAML::Node h = r.Child(n, path, "hand", false); h.IsDefined()) {
    const std::string hand = r.String(n, path, "hand");
    if (hand != "right" && hand != "left") {
      r.Fail(Join(path, "hand"), h, "'" + hand + "'", "must be right or left");
    }
    g.hand = hand == "right" ? Hand::kRight : Hand::kLeft;
  } else if (g.helix_angle != 0.0) {
    r.Fail(Join(path, "hand"), n, "", "required when helix_angle is not 0");
  }
  if (const YAML::Node t = r.Child(n, path, "runout", false); t.IsDefined()) {
    const std::string p = Join(path, "runout");
    r.ExpectMap(t, p, {"amplitude", "phase"});
    g.runout = Runout{r.Quantity(t, p, "amplitude", Dimension::kLength),
                      r.Quantity(t, p, "phase", Dimension::kAngle, 0.0)};
  }
  g.pitch_errors = r.QuantityList(n, path, "pitch_errors", Dimension::kLength, false);
  return g;
}

StiffnessModel ReadStiffness(Reader& r, const YAML::Node& n, const std::string& path) {
  r.ExpectMap(n, path, {"model", "rectangular", "table", "fourier"});
  const std::string model = r.String(n, path, "model", std::string("potential_energy"));
  const std::vector<std::string> models{"potential_energy", "rectangular", "table", "fourier"};
  if (std::find(models.begin(), models.end(), model) == models.end()) {
    std::string rule = "must be one of potential_energy, rectangular, table, fourier";
    const std::string close = ClosestMatch(model, models);
    if (!close.empty()) rule += " (did you mean '" + close + "'?)";
    r.Fail(Join(path, "model"), n["model"], "'" + model + "'", rule);
  }
  for (const char* other : {"rectangular", "table", "fourier"}) {
    if (model != other && n[other].IsDefined()) {
      r.Fail(
          Join(path, other), n[other], "",
          "parameters given for model '" + std::string(other) + "' but model is '" + model + "'");
    }
  }
  if (model == "potential_energy") return PotentialEnergyStiffness{};
  const YAML::Node sub = r.Child(n, path, model, true);
  const std::string p = Join(path, model);
  if (model == "rectangular") {
    r.ExpectMap(sub, p, {"single", "double", "contact_ratio"});
    return RectangularStiffness{r.Quantity(sub, p, "single", Dimension::kStiffness),
                                r.Quantity(sub, p, "double", Dimension::kStiffness),
                                r.Quantity(sub, p, "contact_ratio", Dimension::kDimensionless)};
  }
  if (model == "table") {
    r.ExpectMap(sub, p, {"phase", "stiffness"});
    return TableStiffness{r.QuantityList(sub, p, "phase", Dimension::kDimensionless, true),
                          r.QuantityList(sub, p, "stiffness", Dimension::kStiffness, true)};
  }
  r.ExpectMap(sub, p, {"mean", "cos", "sin"});
  return FourierStiffness{r.Quantity(sub, p, "mean", Dimension::kStiffness),
                          r.QuantityList(sub, p, "cos", Dimension::kStiffness, false),
                          r.QuantityList(sub, p, "sin", Dimension::kStiffness, false)};
}

std::vector<BearingSpec> ReadBearings(Reader& r, const YAML::Node& n, const std::string& path,
                                      bool required) {
  std::vector<BearingSpec> bearings;
  r.ForEachItem(n, path, "bearings", required, [&](const YAML::Node& item, const std::string& p) {
    r.ExpectMap(item, p,
                {"at", "radial_stiffness", "axial_stiffness", "tilt_stiffness", "damping"});
    bearings.push_back({r.Quantity(item, p, "at", Dimension::kLength),
                        r.Quantity(item, p, "radial_stiffness", Dimension::kStiffness, 0.0),
                        r.Quantity(item, p, "axial_stiffness", Dimension::kStiffness, 0.0),
                        r.Quantity(item, p, "tilt_stiffness", Dimension::kRotationalStiffness, 0.0),
                        r.Quantity(item, p, "damping", Dimension::kDamping, 0.0)});
  });
  return bearings;
}

// An elastic shaft. Schema 1 places its one gear with `gear_at`; schema 2 places gears with their
// own `at` and lets lumped bodies carry a mass.
std::vector<std::string> ElasticShaftKeys(int schema) {
  if (schema == 1) {
    return {"material", "segments", "gear_at", "bearings", "inertias", "element_length"};
  }
  return {"material", "segments", "bearings", "inertias", "element_length", "fixed"};
}

ShaftSpec ReadShaft(Reader& r, const YAML::Node& n, const std::string& path,
                    const std::map<std::string, Material>& materials, int schema) {
  r.ExpectMap(n, path, ElasticShaftKeys(schema));
  ShaftSpec s;
  s.material = r.String(n, path, "material");
  if (materials.find(s.material) == materials.end()) {
    r.Fail(Join(path, "material"), n["material"], "'" + s.material + "'",
           "must name a key of materials");
  }
  r.ForEachItem(n, path, "segments", true, [&](const YAML::Node& item, const std::string& p) {
    r.ExpectMap(item, p, {"length", "outer_diameter", "inner_diameter"});
    s.segments.push_back({r.Quantity(item, p, "length", Dimension::kLength),
                          r.Quantity(item, p, "outer_diameter", Dimension::kLength),
                          r.Quantity(item, p, "inner_diameter", Dimension::kLength, 0.0)});
  });
  if (schema == 1) s.gear_at = r.Quantity(n, path, "gear_at", Dimension::kLength);
  s.bearings = ReadBearings(r, n, path, true);
  r.ForEachItem(n, path, "inertias", false, [&](const YAML::Node& item, const std::string& p) {
    if (schema == 1) {
      r.ExpectMap(item, p, {"at", "polar", "diametral"});
    } else {
      r.ExpectMap(item, p, {"at", "polar", "diametral", "mass"});
    }
    s.inertias.push_back({r.Quantity(item, p, "at", Dimension::kLength),
                          r.Quantity(item, p, "polar", Dimension::kInertia, 0.0),
                          r.Quantity(item, p, "diametral", Dimension::kInertia, 0.0),
                          r.Quantity(item, p, "mass", Dimension::kMass, 0.0)});
  });
  s.element_length = r.OptionalQuantity(n, path, "element_length", Dimension::kLength);
  return s;
}

// Parameters an atlas axis may vary, with their dimension.
const std::map<std::string, Dimension>& AtlasParameters() {
  static const std::map<std::string, Dimension> params{
      {"operating.speed", Dimension::kAngularSpeed},
      {"operating.torque", Dimension::kTorque},
      {"mesh.backlash", Dimension::kLength},
      {"mesh.damping_ratio", Dimension::kDimensionless},
      {"mesh.friction_coefficient", Dimension::kDimensionless},
      {"operating.excitation[0].amplitude", Dimension::kAngularAcceleration},
  };
  return params;
}

SweepRange ReadRange(Reader& r, const YAML::Node& n, const std::string& path, Dimension d) {
  SweepRange range{r.Quantity(n, path, "from", d), r.Quantity(n, path, "to", d),
                   r.Integer(n, path, "points")};
  if (r.Child(n, path, "scale", false).IsDefined()) {  // else the struct's default (linear)
    const std::string scale = r.String(n, path, "scale");
    if (scale == "linear") {
      range.scale = AxisScale::kLinear;
    } else if (scale == "log") {
      range.scale = AxisScale::kLog;
    } else {
      r.Fail(Join(path, "scale"), n["scale"], "'" + scale + "'", "must be linear or log");
    }
  }
  return range;
}

AtlasAxis ReadAtlasAxis(Reader& r, const YAML::Node& n, const std::string& path, int schema) {
  r.ExpectMap(n, path, {"parameter", "from", "to", "points", "scale"});
  AtlasAxis axis;
  axis.parameter = r.String(n, path, "parameter");
  std::optional<Dimension> dimension;
  std::string rule;
  if (schema == 2) {
    dimension = app::TrainParameterDimension(axis.parameter);
    if (!dimension) rule = TrainParameterRejection(axis.parameter);
  } else {
    const auto& params = AtlasParameters();
    if (const auto it = params.find(axis.parameter); it != params.end()) {
      dimension = it->second;
    } else {
      std::vector<std::string> names;
      names.reserve(params.size());
      for (const auto& kv : params) names.push_back(kv.first);
      rule = "is not a parameter an atlas can vary";
      const std::string close = ClosestMatch(axis.parameter, names);
      if (!close.empty()) rule += " (did you mean '" + close + "'?)";
    }
  }
  if (!dimension) r.Fail(Join(path, "parameter"), n["parameter"], "'" + axis.parameter + "'", rule);
  axis.range = ReadRange(r, n, path, *dimension);
  return axis;
}

Tier ReadTier(Reader& r, const YAML::Node& map, const std::string& path) {
  const YAML::Node n = r.Child(map, path, "tier", false);
  if (!n.IsDefined()) return Tier::kTier1;
  const std::string p = Join(path, "tier");
  if (!n.IsScalar())
    r.Fail(p, n, Describe(n), "must be 1..5 or \"N40 full\", \"N20 simple\", \"N20 MTA\"");
  const std::string& s = n.Scalar();
  r.Remember(p, n, s);
  static const std::map<std::string, Tier> names{{"1", Tier::kTier1},
                                                 {"2", Tier::kTier2},
                                                 {"3", Tier::kTier3},
                                                 {"4", Tier::kTier4},
                                                 {"5", Tier::kTier5},
                                                 {"N40 full", Tier::kTier5},
                                                 {"N20 simple", Tier::kN20Simple},
                                                 {"N20 MTA", Tier::kN20Mta}};
  if (auto it = names.find(s); it != names.end()) return it->second;
  r.Fail(p, n, "'" + s + "'", "must be 1..5 or \"N40 full\", \"N20 simple\", \"N20 MTA\"");
}

std::map<std::string, Material> ReadMaterials(Reader& r, const YAML::Node& root) {
  std::map<std::string, Material> out;
  const YAML::Node materials = r.Child(root, "", "materials", true);
  r.ExpectMap(materials, "materials", {});
  for (const auto& kv : materials) {
    const std::string key = kv.first.Scalar();
    const std::string p = "materials." + key;
    r.ExpectMap(kv.second, p, {"youngs_modulus", "poisson_ratio", "density"});
    out[key] = Material{r.Quantity(kv.second, p, "youngs_modulus", Dimension::kPressure),
                        r.Quantity(kv.second, p, "poisson_ratio", Dimension::kDimensionless),
                        r.Quantity(kv.second, p, "density", Dimension::kDensity)};
  }
  if (out.empty()) r.Fail("materials", materials, "{}", "needs at least one material");
  return out;
}

MeshSpec ReadMesh(Reader& r, const YAML::Node& mesh, const std::string& path,
                  const std::vector<std::string>& extra_keys) {
  std::vector<std::string> keys{"backlash",        "damping_ratio", "friction_coefficient",
                                "center_distance", "stiffness",     "static_transmission_error",
                                "misalignment"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  r.ExpectMap(mesh, path, keys);
  MeshSpec out;
  out.backlash = r.Quantity(mesh, path, "backlash", Dimension::kLength);
  out.damping_ratio =
      r.Quantity(mesh, path, "damping_ratio", Dimension::kDimensionless, out.damping_ratio);
  out.friction_coefficient = r.Quantity(mesh, path, "friction_coefficient",
                                        Dimension::kDimensionless, out.friction_coefficient);
  out.center_distance = r.OptionalQuantity(mesh, path, "center_distance", Dimension::kLength);
  out.misalignment = r.Quantity(mesh, path, "misalignment", Dimension::kLength, 0.0);
  if (const YAML::Node s = r.Child(mesh, path, "stiffness", false); s.IsDefined()) {
    out.stiffness = ReadStiffness(r, s, Join(path, "stiffness"));
  }
  if (const YAML::Node s = r.Child(mesh, path, "static_transmission_error", false); s.IsDefined()) {
    const std::string p = Join(path, "static_transmission_error");
    r.ExpectMap(s, p, {"amplitudes", "phases"});
    out.static_transmission_error.amplitudes =
        r.QuantityList(s, p, "amplitudes", Dimension::kLength, true);
    out.static_transmission_error.phases = r.QuantityList(s, p, "phases", Dimension::kAngle, true);
  }
  return out;
}

std::vector<ExcitationOrder> ReadExcitation(Reader& r, const YAML::Node& op, int schema) {
  std::vector<ExcitationOrder> out;
  r.ForEachItem(
      op, "operating", "excitation", false, [&](const YAML::Node& item, const std::string& p) {
        if (schema == 2) {
          r.ExpectMap(item, p, {"kind", "on", "order", "amplitude", "phase"});
        } else {
          r.ExpectMap(item, p, {"kind", "order", "amplitude", "phase"});
        }
        const std::string kind = r.String(item, p, "kind", std::string("acceleration"));
        if (kind == "motion") {
          r.Fail(Join(p, "kind"), item["kind"], "'" + kind + "'",
                 schema == 2 ? "is not built yet: prescribed motion of a shaft is planned; give "
                               "the engine's torque orders (kind: torque) on a free flywheel "
                               "instead"
                             : "is not built yet: prescribed motion of a shaft is planned; a "
                               "pair's order is an acceleration (kind: acceleration)");
        }
        if (kind != "acceleration" && (kind != "torque" || schema != 2)) {
          r.Fail(Join(p, "kind"), item["kind"], "'" + kind + "'",
                 schema == 2 ? "must be acceleration (the torque J a on its shaft) or torque"
                             : "must be acceleration, schema 1's one kind (the torque J a on "
                               "the pinion's shaft); torque orders on any shaft need a gear "
                               "train (schema gearnvh/2)");
        }
        ExcitationOrder e;
        e.kind = kind == "torque" ? ExcitationKind::kTorque : ExcitationKind::kAcceleration;
        e.order = r.Quantity(item, p, "order", Dimension::kDimensionless);
        e.amplitude =
            r.Quantity(item, p, "amplitude",
                       e.kind == ExcitationKind::kTorque ? Dimension::kTorque
                                                         : Dimension::kAngularAcceleration);
        e.phase = r.Quantity(item, p, "phase", Dimension::kAngle, 0.0);
        if (schema == 2) {
          e.on = r.String(item, p, "on", "");
          if (item["on"].IsDefined() && e.on.empty()) {
            r.Fail(Join(p, "on"), item["on"], "''",
                   "must name a shaft (leave the key out for the input shaft)");
          }
        }
        out.push_back(e);
      });
  return out;
}

std::string HoldSpeedsToPitchLineLimit(AnalysisSpec& analysis, const SourceLocations& where,
                                       const DisplayUnit& speed_unit, double velocity_per_speed,
                                       const std::string& mesh) {
  const auto require = [&](const SweepRange& range, const std::string& path) {
    const DisplayUnit unit = DisplayUnitOf(where.Find(path + ".to").raw, Dimension::kAngularSpeed);
    RequirePitchLineVelocity(path + ".from", range.from, unit, velocity_per_speed, mesh);
    RequirePitchLineVelocity(path + ".to", range.to, unit, velocity_per_speed, mesh);
  };
  for (const auto& [axis, path] : {std::pair{&analysis.atlas_x, "analysis.atlas.x"},
                                   std::pair{&analysis.atlas_y, "analysis.atlas.y"}}) {
    if (*axis && (*axis)->parameter == "operating.speed") require((*axis)->range, path);
  }
  SweepRange& sweep = analysis.speed_sweep;
  if (where.Exact("analysis.speed_sweep.to")) {
    require(sweep, "analysis.speed_sweep");
    return "";
  }
  // A hair below the limit, so rounding cannot put the last speed above it.
  const double highest = GearboxLimits::kMaxPitchLineVelocity / velocity_per_speed * (1.0 - 1e-9);
  if (sweep.to <= highest) return "";
  const SweepRange default_sweep = sweep;
  // Keep the default's span ratio when even its lowest speed is too fast.
  if (sweep.from >= highest) sweep.from = highest * sweep.from / sweep.to;
  sweep.to = highest;
  return fmt::format(
      "analysis.speed_sweep is not written, and the default sweep {} to {} would run {} above the "
      "pitch-line velocity limit of {} m/s (at {:.4g} m/s): sweeping {} to {} instead, the "
      "largest speed allowed (write analysis.speed_sweep to choose the range)",
      InUnit(default_sweep.from, speed_unit), InUnit(default_sweep.to, speed_unit), mesh,
      GearboxLimits::kMaxPitchLineVelocity, default_sweep.to * velocity_per_speed,
      InUnit(sweep.from, speed_unit), InUnit(sweep.to, speed_unit));
}

AnalysisSpec ReadAnalysis(Reader& r, const YAML::Node& root, int schema) {
  AnalysisSpec an;
  const YAML::Node a = r.Child(root, "", "analysis", false);
  if (!a.IsDefined()) return an;
  r.ExpectMap(a, "analysis",
              {"tier", "segments_per_cycle", "cycles", "transient_cycles", "speed_sweep", "atlas"});
  an.tier = ReadTier(r, a, "analysis");
  an.segments_per_cycle = r.Integer(a, "analysis", "segments_per_cycle", an.segments_per_cycle);
  an.cycles = r.Integer(a, "analysis", "cycles", an.cycles);
  an.transient_cycles = r.Integer(a, "analysis", "transient_cycles", an.transient_cycles);
  if (const YAML::Node s = r.Child(a, "analysis", "speed_sweep", false); s.IsDefined()) {
    r.ExpectMap(s, "analysis.speed_sweep", {"from", "to", "points", "scale"});
    an.speed_sweep = ReadRange(r, s, "analysis.speed_sweep", Dimension::kAngularSpeed);
  }
  if (const YAML::Node at = r.Child(a, "analysis", "atlas", false); at.IsDefined()) {
    r.ExpectMap(at, "analysis.atlas", {"x", "y"});
    an.atlas_x =
        ReadAtlasAxis(r, r.Child(at, "analysis.atlas", "x", true), "analysis.atlas.x", schema);
    an.atlas_y =
        ReadAtlasAxis(r, r.Child(at, "analysis.atlas", "y", true), "analysis.atlas.y", schema);
  }
  return an;
}

// The schema version a document declares (gearnvh/1 when absent).
int SchemaOf(Reader& r, const YAML::Node& root) {
  if (root.IsNull() || !root.IsDefined()) {
    r.Fail("", root, "", "the document is empty; expected a gearbox mapping (schema: gearnvh/1)");
  }
  if (!root.IsMap()) r.Fail("", root, Describe(root), "must be a mapping");
  const std::string schema = r.String(root, "", "schema", std::string("gearnvh/1"));
  if (schema == "gearnvh/1") return 1;
  if (schema == "gearnvh/2") return 2;
  r.Fail("schema", root["schema"], "'" + schema + "'",
         "must be gearnvh/1 or gearnvh/2 (the versions this program reads)");
}

}  // namespace gearnvh::config
