#include "gearbox_loader.h"
#include "utf8_check.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"
#include "units.h"

namespace gearnvh::config {
namespace {

constexpr size_t kMaxFileBytes = 16u << 20;

int LineOf(const YAML::Node& n) {
  const int line = n.Mark().line;
  return line >= 0 ? line + 1 : 0;
}

std::string Join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string Describe(const YAML::Node& n) {
  switch (n.Type()) {
    case YAML::NodeType::Map:
      return "a mapping";
    case YAML::NodeType::Sequence:
      return "a list";
    case YAML::NodeType::Null:
      return "nothing (null)";
    case YAML::NodeType::Scalar:
      return "'" + n.Scalar() + "'";
    default:
      return "an undefined node";
  }
}

// Walks one YAML document, remembering the line and raw text of every path it reads so range
// errors found later (ValidateGearboxSpec) can point back at the source.
class Reader {
 public:
  struct Location {
    int line = 0;
    std::string raw;
  };

  [[noreturn]] void Fail(const std::string& path, const YAML::Node& n, const std::string& value,
                         const std::string& rule) const {
    throw InputError(path, LineOf(n), value, rule);
  }

  // Checks that `n` is a mapping whose keys are unique scalars from `allowed`.
  void ExpectMap(const YAML::Node& n, const std::string& path,
                 const std::vector<std::string>& allowed) {
    if (!n.IsMap()) Fail(path, n, Describe(n), "must be a mapping");
    Remember(path, n, "");
    std::vector<std::string> seen;
    for (const auto& kv : n) {
      if (!kv.first.IsScalar())
        Fail(path, kv.first, Describe(kv.first), "keys must be plain names");
      const std::string key = kv.first.Scalar();
      if (std::find(seen.begin(), seen.end(), key) != seen.end()) {
        Fail(Join(path, key), kv.first, key, "duplicate key");
      }
      seen.push_back(key);
      if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string rule = "unknown key";
        const std::string close = ClosestMatch(key, allowed);
        if (!close.empty())
          rule += " (did you mean '" + close + "'?)";
        else
          rule += "; allowed here: " + JoinList(allowed);
        Fail(Join(path, key), kv.first, key, rule);
      }
    }
  }

  // Returns the child, or an invalid node when absent. Throws when `required` and absent.
  YAML::Node Child(const YAML::Node& map, const std::string& path, const std::string& key,
                   bool required) {
    YAML::Node child = map[key];
    if (!child.IsDefined()) {
      if (required) Fail(Join(path, key), map, "", "required key is missing");
      return child;
    }
    return child;
  }

  double Quantity(const YAML::Node& map, const std::string& path, const std::string& key,
                  Dimension d, std::optional<double> fallback = std::nullopt) {
    const YAML::Node n = Child(map, path, key, !fallback.has_value());
    if (!n.IsDefined()) return *fallback;
    return QuantityNode(n, Join(path, key), d);
  }

  std::optional<double> OptionalQuantity(const YAML::Node& map, const std::string& path,
                                         const std::string& key, Dimension d) {
    const YAML::Node n = Child(map, path, key, false);
    if (!n.IsDefined()) return std::nullopt;
    return QuantityNode(n, Join(path, key), d);
  }

  double QuantityNode(const YAML::Node& n, const std::string& path, Dimension d) {
    if (!n.IsScalar()) {
      Fail(path, n, Describe(n),
           std::string("must be a ") + DimensionName(d) +
               (d == Dimension::kDimensionless ? "" : " such as a number with a unit"));
    }
    const ParsedQuantity q = ParseQuantity(n.Scalar(), d);
    if (!q.error.empty()) Fail(path, n, "'" + n.Scalar() + "'", q.error);
    Remember(path, n, n.Scalar());
    return q.si_value;
  }

  int Integer(const YAML::Node& map, const std::string& path, const std::string& key,
              std::optional<int> fallback = std::nullopt) {
    const YAML::Node n = Child(map, path, key, !fallback.has_value());
    if (!n.IsDefined()) return *fallback;
    const std::string p = Join(path, key);
    if (!n.IsScalar()) Fail(p, n, Describe(n), "must be an integer");
    const auto v = ParseNumber(n.Scalar());
    if (!v || std::floor(*v) != *v || std::abs(*v) > 2e9) {
      Fail(p, n, "'" + n.Scalar() + "'", "must be an integer");
    }
    Remember(p, n, n.Scalar());
    return static_cast<int>(*v);
  }

  std::string String(const YAML::Node& map, const std::string& path, const std::string& key,
                     std::optional<std::string> fallback = std::nullopt) {
    const YAML::Node n = Child(map, path, key, !fallback.has_value());
    if (!n.IsDefined()) return *fallback;
    const std::string p = Join(path, key);
    if (!n.IsScalar()) Fail(p, n, Describe(n), "must be a text");
    Remember(p, n, n.Scalar());
    return n.Scalar();
  }

  std::vector<double> QuantityList(const YAML::Node& map, const std::string& path,
                                   const std::string& key, Dimension d, bool required) {
    const YAML::Node n = Child(map, path, key, required);
    std::vector<double> out;
    if (!n.IsDefined()) return out;
    const std::string p = Join(path, key);
    if (!n.IsSequence()) Fail(p, n, Describe(n), "must be a list");
    Remember(p, n, "");
    for (size_t i = 0; i < n.size(); ++i) {
      out.push_back(QuantityNode(n[i], p + "[" + std::to_string(i) + "]", d));
    }
    return out;
  }

  // A list of mappings; calls `each(node, path)` for every item.
  template <typename F>
  void ForEachItem(const YAML::Node& map, const std::string& path, const std::string& key,
                   bool required, F&& each) {
    const YAML::Node n = Child(map, path, key, required);
    if (!n.IsDefined()) return;
    const std::string p = Join(path, key);
    if (!n.IsSequence()) Fail(p, n, Describe(n), "must be a list");
    Remember(p, n, "");
    for (size_t i = 0; i < n.size(); ++i) each(n[i], p + "[" + std::to_string(i) + "]");
  }

  void Remember(const std::string& path, const YAML::Node& n, const std::string& raw) {
    locations_[path] = Location{LineOf(n), raw};
  }

  // The location of `path`, or of its longest known prefix.
  Location Find(std::string path) const {
    while (true) {
      if (auto it = locations_.find(path); it != locations_.end()) return it->second;
      const auto cut = path.find_last_of(".[");
      if (cut == std::string::npos) return {};
      path = path.substr(0, cut);
    }
  }

  bool Exact(const std::string& path) const { return locations_.count(path) > 0; }

 private:
  static std::string JoinList(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  }
  std::map<std::string, Location> locations_;
};

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
                                         "helix_angle",
                                         "hand",
                                         "runout",
                                         "pitch_errors"};

GearSpec ReadGear(Reader& r, const YAML::Node& n, const std::string& path,
                  const std::map<std::string, Material>& materials,
                  const std::vector<std::string>& extra_keys = {}) {
  std::vector<std::string> keys = kGearKeys;
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  r.ExpectMap(n, path, keys);
  GearSpec g;
  g.teeth = r.Integer(n, path, "teeth");
  g.module = r.Quantity(n, path, "module", Dimension::kLength);
  g.pressure_angle =
      r.Quantity(n, path, "pressure_angle", Dimension::kAngle, g.pressure_angle);
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
  g.addendum_coefficient =
      r.Quantity(n, path, "addendum_coefficient", Dimension::kDimensionless, g.addendum_coefficient);
  g.dedendum_coefficient =
      r.Quantity(n, path, "dedendum_coefficient", Dimension::kDimensionless, g.dedendum_coefficient);
  g.profile_shift = r.Quantity(n, path, "profile_shift", Dimension::kDimensionless, g.profile_shift);
  g.inertia = r.OptionalQuantity(n, path, "inertia", Dimension::kInertia);
  g.mass = r.OptionalQuantity(n, path, "mass", Dimension::kMass);
  if (const YAML::Node t = r.Child(n, path, "tip_relief", false); t.IsDefined()) {
    const std::string p = Join(path, "tip_relief");
    r.ExpectMap(t, p, {"amount", "length"});
    g.tip_relief = TipRelief{r.Quantity(t, p, "amount", Dimension::kLength),
                             r.Quantity(t, p, "length", Dimension::kLength)};
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
    bearings.push_back(
        {r.Quantity(item, p, "at", Dimension::kLength),
         r.Quantity(item, p, "radial_stiffness", Dimension::kStiffness, 0.0),
         r.Quantity(item, p, "axial_stiffness", Dimension::kStiffness, 0.0),
         r.Quantity(item, p, "tilt_stiffness", Dimension::kRotationalStiffness, 0.0),
         r.Quantity(item, p, "damping", Dimension::kDamping, 0.0)});
  });
  return bearings;
}

// An elastic shaft. Schema 1 places its one gear with `gear_at`; schema 2 places gears with their
// own `at` and lets lumped bodies carry a mass.
ShaftSpec ReadShaft(Reader& r, const YAML::Node& n, const std::string& path,
                    const std::map<std::string, Material>& materials, int schema = 1) {
  if (schema == 1) {
    r.ExpectMap(n, path,
                {"material", "segments", "gear_at", "bearings", "inertias", "element_length"});
  } else {
    r.ExpectMap(n, path, {"material", "segments", "bearings", "inertias", "element_length"});
  }
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
  return SweepRange{r.Quantity(n, path, "from", d), r.Quantity(n, path, "to", d),
                    r.Integer(n, path, "points")};
}

AtlasAxis ReadAtlasAxis(Reader& r, const YAML::Node& n, const std::string& path) {
  r.ExpectMap(n, path, {"parameter", "from", "to", "points"});
  AtlasAxis axis;
  axis.parameter = r.String(n, path, "parameter");
  const auto& params = AtlasParameters();
  const auto it = params.find(axis.parameter);
  if (it == params.end()) {
    std::vector<std::string> names;
    names.reserve(params.size());
    for (const auto& kv : params) names.push_back(kv.first);
    std::string rule = "is not a parameter an atlas can vary";
    const std::string close = ClosestMatch(axis.parameter, names);
    if (!close.empty()) rule += " (did you mean '" + close + "'?)";
    r.Fail(Join(path, "parameter"), n["parameter"], "'" + axis.parameter + "'", rule);
  }
  axis.range = ReadRange(r, n, path, it->second);
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
                  const std::vector<std::string>& extra_keys = {}) {
  std::vector<std::string> keys{"backlash",  "damping_ratio", "friction_coefficient",
                                "center_distance", "stiffness", "static_transmission_error"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  r.ExpectMap(mesh, path, keys);
  MeshSpec out;
  out.backlash = r.Quantity(mesh, path, "backlash", Dimension::kLength);
  out.damping_ratio =
      r.Quantity(mesh, path, "damping_ratio", Dimension::kDimensionless, out.damping_ratio);
  out.friction_coefficient =
      r.Quantity(mesh, path, "friction_coefficient", Dimension::kDimensionless,
                 out.friction_coefficient);
  out.center_distance = r.OptionalQuantity(mesh, path, "center_distance", Dimension::kLength);
  if (const YAML::Node s = r.Child(mesh, path, "stiffness", false); s.IsDefined()) {
    out.stiffness = ReadStiffness(r, s, Join(path, "stiffness"));
  }
  if (const YAML::Node s = r.Child(mesh, path, "static_transmission_error", false);
      s.IsDefined()) {
    const std::string p = Join(path, "static_transmission_error");
    r.ExpectMap(s, p, {"amplitudes", "phases"});
    out.static_transmission_error.amplitudes =
        r.QuantityList(s, p, "amplitudes", Dimension::kLength, true);
    out.static_transmission_error.phases = r.QuantityList(s, p, "phases", Dimension::kAngle, true);
  }
  return out;
}

std::vector<ExcitationOrder> ReadExcitation(Reader& r, const YAML::Node& op) {
  std::vector<ExcitationOrder> out;
  r.ForEachItem(op, "operating", "excitation", false,
                [&](const YAML::Node& item, const std::string& p) {
                  r.ExpectMap(item, p, {"order", "amplitude", "phase"});
                  out.push_back({r.Quantity(item, p, "order", Dimension::kDimensionless),
                                 r.Quantity(item, p, "amplitude", Dimension::kAngularAcceleration),
                                 r.Quantity(item, p, "phase", Dimension::kAngle, 0.0)});
                });
  return out;
}

AnalysisSpec ReadAnalysis(Reader& r, const YAML::Node& root) {
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
    r.ExpectMap(s, "analysis.speed_sweep", {"from", "to", "points"});
    an.speed_sweep = ReadRange(r, s, "analysis.speed_sweep", Dimension::kAngularSpeed);
  }
  if (const YAML::Node at = r.Child(a, "analysis", "atlas", false); at.IsDefined()) {
    r.ExpectMap(at, "analysis.atlas", {"x", "y"});
    an.atlas_x = ReadAtlasAxis(r, r.Child(at, "analysis.atlas", "x", true), "analysis.atlas.x");
    an.atlas_y = ReadAtlasAxis(r, r.Child(at, "analysis.atlas", "y", true), "analysis.atlas.y");
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

GearboxSpec ReadDocument(Reader& r, const YAML::Node& root) {
  r.ExpectMap(root, "",
              {"schema", "name", "materials", "gears", "mesh", "shafts", "operating", "analysis"});
  GearboxSpec spec;
  spec.name = r.String(root, "", "name");
  spec.materials = ReadMaterials(r, root);

  const YAML::Node gears = r.Child(root, "", "gears", true);
  r.ExpectMap(gears, "gears", {"pinion", "wheel"});
  spec.pinion =
      ReadGear(r, r.Child(gears, "gears", "pinion", true), "gears.pinion", spec.materials);
  spec.wheel = ReadGear(r, r.Child(gears, "gears", "wheel", true), "gears.wheel", spec.materials);
  spec.mesh = ReadMesh(r, r.Child(root, "", "mesh", true), "mesh");

  if (const YAML::Node shafts = r.Child(root, "", "shafts", false); shafts.IsDefined()) {
    r.ExpectMap(shafts, "shafts", {"input", "output"});
    if (const YAML::Node in = shafts["input"]; in.IsDefined()) {
      spec.input_shaft = ReadShaft(r, in, "shafts.input", spec.materials);
    }
    if (const YAML::Node out = shafts["output"]; out.IsDefined()) {
      spec.output_shaft = ReadShaft(r, out, "shafts.output", spec.materials);
    }
  }

  const YAML::Node op = r.Child(root, "", "operating", true);
  r.ExpectMap(op, "operating", {"speed", "torque", "torque_on", "excitation"});
  spec.operating.speed = r.Quantity(op, "operating", "speed", Dimension::kAngularSpeed);
  spec.operating.torque = r.Quantity(op, "operating", "torque", Dimension::kTorque);
  if (const std::string on = r.String(op, "operating", "torque_on", std::string("wheel"));
      on == "pinion") {
    spec.operating.torque_on = TorqueOn::kPinion;
  } else if (on != "wheel") {
    r.Fail("operating.torque_on", op["torque_on"], "'" + on + "'", "must be wheel or pinion");
  }
  spec.operating.speed_unit =
      DisplayUnitOf(r.Find("operating.speed").raw, Dimension::kAngularSpeed);
  spec.operating.torque_unit = DisplayUnitOf(r.Find("operating.torque").raw, Dimension::kTorque);
  spec.operating.excitation = ReadExcitation(r, op);
  spec.analysis = ReadAnalysis(r, root);
  return spec;
}

// Schema gearnvh/2: shafts, gears and meshes by name.
TrainSpec ReadTrainDocument(Reader& r, const YAML::Node& root) {
  r.ExpectMap(root, "",
              {"schema", "name", "materials", "shafts", "gears", "meshes", "operating", "analysis"});
  TrainSpec spec;
  spec.name = r.String(root, "", "name");
  spec.materials = ReadMaterials(r, root);

  const YAML::Node shafts = r.Child(root, "", "shafts", true);
  r.ExpectMap(shafts, "shafts", {});
  for (const auto& kv : shafts) {
    TrainShaft shaft;
    shaft.name = kv.first.Scalar();
    const std::string p = "shafts." + shaft.name;
    if (!kv.second.IsMap()) r.Fail(p, kv.second, Describe(kv.second), "must be a mapping");
    if (kv.second["segments"].IsDefined()) {
      shaft.elastic = ReadShaft(r, kv.second, p, spec.materials, 2);
    } else {
      r.ExpectMap(kv.second, p, {"inertia", "bearings"});
      shaft.inertia = r.Quantity(kv.second, p, "inertia", Dimension::kInertia);
      shaft.bearings = ReadBearings(r, kv.second, p, false);
    }
    spec.shafts.push_back(shaft);
  }
  if (spec.shafts.empty()) r.Fail("shafts", shafts, "{}", "needs at least one shaft");

  const YAML::Node gears = r.Child(root, "", "gears", true);
  r.ExpectMap(gears, "gears", {});
  for (const auto& kv : gears) {
    TrainGear gear;
    gear.name = kv.first.Scalar();
    const std::string p = "gears." + gear.name;
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
    mesh.mesh = ReadMesh(r, item, p, {"gears"});
    const YAML::Node pair = r.Child(item, p, "gears", true);
    if (!pair.IsSequence() || pair.size() != 2 || !pair[0].IsScalar() || !pair[1].IsScalar()) {
      r.Fail(Join(p, "gears"), pair, Describe(pair), "must be a list of two gear names");
    }
    r.Remember(Join(p, "gears"), pair, "");
    mesh.gear_a = pair[0].Scalar();
    mesh.gear_b = pair[1].Scalar();
    spec.meshes.push_back(mesh);
  });

  const YAML::Node op = r.Child(root, "", "operating", true);
  r.ExpectMap(op, "operating", {"speed", "loads", "excitation"});
  const YAML::Node speed = r.Child(op, "operating", "speed", true);
  r.ExpectMap(speed, "operating.speed", {"shaft", "value"});
  spec.operating.input_shaft = r.String(speed, "operating.speed", "shaft");
  spec.operating.speed = r.Quantity(speed, "operating.speed", "value", Dimension::kAngularSpeed);
  r.ForEachItem(op, "operating", "loads", false, [&](const YAML::Node& item, const std::string& p) {
    r.ExpectMap(item, p, {"on", "torque"});
    spec.operating.loads.push_back(
        {r.String(item, p, "on"), r.Quantity(item, p, "torque", Dimension::kTorque)});
  });
  spec.operating.excitation = ReadExcitation(r, op);
  spec.analysis = ReadAnalysis(r, root);
  return spec;
}

size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t sub = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, sub});
    }
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

}  // namespace

std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = EditDistance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

namespace {

YAML::Node ParseYaml(const std::string& text, const std::string& source) {
  RequireValidUtf8(text, source);
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const int line = e.mark.line >= 0 ? e.mark.line + 1 : 0;
    throw InputError("", line, "", "not valid YAML: " + e.msg, source);
  }
}

// Reads the document with `read`, validates it with `validate`, and attributes every error to
// `source`, with range errors pointed back at the line and the value as the user wrote it.
template <typename Read, typename Validate>
auto ReadAndValidate(const YAML::Node& root, const std::string& source, Read&& read,
                     Validate&& validate) {
  Reader reader;
  try {
    auto spec = read(reader, root);
    try {
      validate(spec);
    } catch (const InputError& e) {
      const Reader::Location loc = reader.Find(e.path());
      const std::string value =
          reader.Exact(e.path()) && !loc.raw.empty() ? "'" + loc.raw + "'" : e.value();
      throw InputError(e.path(), loc.line, value, e.rule(), source);
    }
    return spec;
  } catch (const InputError& e) {
    if (!e.source().empty()) throw;
    throw e.WithSource(source);
  } catch (const YAML::Exception& e) {
    const int line = e.mark.line >= 0 ? e.mark.line + 1 : 0;
    throw InputError("", line, "", "cannot be read: " + e.msg, source);
  }
}


}  // namespace

GearboxSpec LoadGearboxFromString(const std::string& text, const std::string& source) {
  const YAML::Node root = ParseYaml(text, source);
  return ReadAndValidate(
      root, source,
      [](Reader& r, const YAML::Node& n) {
        if (SchemaOf(r, n) == 2) {
          r.Fail("schema", n["schema"], "'gearnvh/2'",
                 "gear trains are checked (`gearnvh check`) but not yet simulated; this command "
                 "reads gearnvh/1");
        }
        return ReadDocument(r, n);
      },
      [](const GearboxSpec& spec) { ValidateGearboxSpec(spec); });
}

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
    out.pair = LoadGearboxFromString(text, source);
    out.train = TrainOf(*out.pair);
    return out;
  }
  out.train = ReadAndValidate(root, source, ReadTrainDocument,
                              [](const TrainSpec& spec) { ValidateTrainSpec(spec); });
  return out;
}

AtlasAxis ParseAxisOption(const std::string& text, const std::string& field) {
  const std::string form =
      "must be PARAMETER=FROM:TO:POINTS, e.g. operating.speed=600rpm:3000rpm:24";
  const size_t eq = text.find('=');
  if (eq == std::string::npos) throw InputError(field, 0, "'" + text + "'", form);
  AtlasAxis axis;
  axis.parameter = text.substr(0, eq);
  const auto& params = AtlasParameters();
  const auto it = params.find(axis.parameter);
  if (it == params.end()) {
    std::vector<std::string> names;
    for (const auto& kv : params) names.push_back(kv.first);
    std::string rule = "is not a parameter that can be varied";
    const std::string close = ClosestMatch(axis.parameter, names);
    if (!close.empty()) rule += " (did you mean '" + close + "'?)";
    throw InputError(field, 0, "'" + axis.parameter + "'", rule);
  }
  const std::string rest = text.substr(eq + 1);
  const size_t c1 = rest.find(':');
  const size_t c2 = c1 == std::string::npos ? c1 : rest.find(':', c1 + 1);
  if (c2 == std::string::npos) throw InputError(field, 0, "'" + text + "'", form);
  const ParsedQuantity from = ParseQuantity(rest.substr(0, c1), it->second);
  const ParsedQuantity to = ParseQuantity(rest.substr(c1 + 1, c2 - c1 - 1), it->second);
  const auto points = ParseNumber(rest.substr(c2 + 1));
  if (!from.error.empty()) throw InputError(field, 0, "'" + rest.substr(0, c1) + "'", from.error);
  if (!to.error.empty()) {
    throw InputError(field, 0, "'" + rest.substr(c1 + 1, c2 - c1 - 1) + "'", to.error);
  }
  if (!points || *points < 1 || *points != std::floor(*points) || *points > 100000) {
    throw InputError(field, 0, "'" + rest.substr(c2 + 1) + "'",
                     "POINTS must be a whole number in 1..100000");
  }
  axis.range = {from.si_value, to.si_value, static_cast<int>(*points)};
  return axis;
}

std::string ReadGearboxText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw InputError("", 0, "", std::string("cannot open file: ") + std::strerror(errno), path);
  std::string text;
  char buffer[65536];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    text.append(buffer, static_cast<size_t>(in.gcount()));
    if (text.size() > kMaxFileBytes) {
      throw InputError("", 0, "", "file is larger than 16 MiB; not a gearbox definition", path);
    }
  }
  if (in.bad()) throw InputError("", 0, "", "read error", path);
  return text;
}

GearboxSpec LoadGearboxFile(const std::string& path) {
  return LoadGearboxFromString(ReadGearboxText(path), path);
}

LoadedGearbox LoadAnyGearboxFile(const std::string& path) {
  return LoadAnyGearboxFromString(ReadGearboxText(path), path);
}

}  // namespace gearnvh::config
