#include "gearbox_loader.h"

#include <fmt/format.h>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/gearbox_spec_validation.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "spec_sections.h"
#include "units.h"
#include "utf8_check.h"
#include "yaml_reader.h"

namespace gearnvh::config {
namespace {

constexpr size_t kMaxFileBytes = 16u << 20;
constexpr size_t kMaxKeyCharacters = 1024;  // of an implicit key (YAML 1.2, 7.4.2)

// A document without a `schema:` line is read as gearnvh/1; a gear train's keys then say which
// line is missing.
void RequireSchemaLineForTrainKeys(Reader& r, const YAML::Node& root) {
  if (root["schema"].IsDefined()) return;
  std::string key;
  if (root["meshes"].IsDefined()) {
    key = "meshes";
  } else if (const YAML::Node shafts = root["shafts"]; shafts.IsDefined() && shafts.IsMap()) {
    for (const auto& kv : shafts) {
      const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : "";
      if (name != "input" && name != "output") {
        key = "shafts." + name;
        break;
      }
    }
  }
  if (key.empty()) return;
  const YAML::Node at = key == "meshes" ? root["meshes"] : root["shafts"];
  r.Fail(key, at, key == "meshes" ? "meshes" : key.substr(7),
         "is a gear-train (schema gearnvh/2) key, but the document has no `schema:` line and is "
         "read as gearnvh/1: write `schema: gearnvh/2` as its first line");
}

GearboxSpec ReadDocument(Reader& r, const YAML::Node& root) {
  RequireSchemaLineForTrainKeys(r, root);
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
  spec.operating.excitation = ReadExcitation(r, op, 1);
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

InputError AtParameterValue(const InputError& e, const std::vector<ParameterValue>& set,
                            const std::function<std::string(const ParameterValue&)>& shown) {
  for (const ParameterValue& p : set) {
    if (e.path() == p.name || e.path() == p.name + ".value") {
      return e.Located(e.line(), shown(p), e.source(), nullptr);
    }
  }
  return e;
}

std::string AxisValueText(double shown_value, const std::string& unit) {
  const std::string number = fmt::format("{:.6g}", shown_value);
  return unit.empty() ? number : number + " " + unit;
}

std::string YamlSyntaxRule(const YAML::Exception& e, const std::string& text) {
  if (const auto* deep = dynamic_cast<const YAML::DeepRecursion*>(&e)) {
    return "not valid YAML here: lists and mappings nested " + std::to_string(deep->depth()) +
           " levels deep, more than the parser allows (a gearbox needs a few)";
  }
  std::string rule = "not valid YAML: " + e.msg;
  // yaml-cpp reports a tab in the indentation as some other error at that line or the next, and a
  // key longer than YAML's 1024 characters as a value without a key.
  std::istringstream lines(text);
  std::string line;
  for (int i = 0; std::getline(lines, line) && i <= e.mark.line; ++i) {
    const std::string indent = line.substr(0, line.find_first_not_of(" \t"));
    if (i == e.mark.line && e.msg == YAML::ErrorMsg::MAP_VALUE) {
      const size_t colon = std::min(line.size(), static_cast<size_t>(std::max(0, e.mark.column)));
      const size_t key = colon > indent.size() ? colon - indent.size() : 0;
      if (key > kMaxKeyCharacters) {
        return fmt::format(
            "has a key of {} bytes (column {} to {}): YAML allows a key of at most {} "
            "characters, and a gearbox's keys and names are short",
            key, indent.size() + 1, colon, kMaxKeyCharacters);
      }
    }
    if (i + 1 >= e.mark.line && indent.find('\t') != std::string::npos) {
      return rule + " (line " + std::to_string(i + 1) +
             " is indented with a tab: YAML indents with spaces only)";
    }
  }
  return rule;
}

YAML::Node ParseYaml(const std::string& text, const std::string& source) {
  RequireValidUtf8(text, source);
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const int line = e.mark.line >= 0 ? e.mark.line + 1 : 0;
    throw InputError("", line, "", YamlSyntaxRule(e, text), source);
  }
}

GearboxSpec LoadGearboxFromString(const std::string& text, const std::string& source) {
  SourceLocations where;
  std::string sweep_note;
  return LoadPairFromString(text, source, where, sweep_note);
}

GearboxSpec LoadPairFromString(const std::string& text, const std::string& source,
                               SourceLocations& where, std::string& sweep_note) {
  const YAML::Node root = ParseYaml(text, source);
  return ReadAndValidate(
      root, source,
      [](Reader& r, const YAML::Node& n) {
        if (SchemaOf(r, n) == 2) {
          r.Fail("schema", n["schema"], "'gearnvh/2'",
                 "this loader reads one pair (gearnvh/1); a gear train is read by the loader of "
                 "either schema (LoadAnyGearboxFromString)");
        }
        return ReadDocument(r, n);
      },
      [&where, &sweep_note](GearboxSpec& spec) {
        ValidateGearboxSpec(spec);
        for (const auto& [axis, path] :
             {std::pair{&spec.analysis.atlas_x, "analysis.atlas.x.parameter"},
              std::pair{&spec.analysis.atlas_y, "analysis.atlas.y.parameter"}}) {
          if (*axis) RequireVariableParameter(spec, (*axis)->parameter, path);
        }
        sweep_note = HoldSpeedsToPitchLineLimit(spec.analysis, where, spec.operating.speed_unit,
                                                PitchRadius(spec.pinion), "the mesh");
      },
      where);
}

AtlasAxis ParseAxisOption(const std::string& text, const std::string& field) {
  const auto& params = AtlasParameters();
  return ParseAxisOption(
      text, field,
      [&](const std::string& name) -> std::optional<Dimension> {
        const auto it = params.find(name);
        return it == params.end() ? std::nullopt : std::optional<Dimension>(it->second);
      },
      [&](const std::string& name) {
        std::vector<std::string> names;
        for (const auto& kv : params) names.push_back(kv.first);
        std::string rule = "is not a parameter that can be varied";
        const std::string close = ClosestMatch(name, names);
        if (!close.empty()) rule += " (did you mean '" + close + "'?)";
        return rule;
      });
}

AtlasAxis ParseAxisOption(
    const std::string& text, const std::string& field,
    const std::function<std::optional<Dimension>(const std::string&)>& dimension_of,
    const std::function<std::string(const std::string&)>& rejection) {
  const std::string form =
      "must be PARAMETER=FROM:TO:POINTS, e.g. operating.speed=600rpm:3000rpm:24";
  const size_t eq = text.find('=');
  if (eq == std::string::npos) throw InputError(field, 0, "'" + text + "'", form);
  AtlasAxis axis;
  axis.parameter = text.substr(0, eq);
  const std::optional<Dimension> dimension = dimension_of(axis.parameter);
  if (!dimension) throw InputError(field, 0, "'" + axis.parameter + "'", rejection(axis.parameter));
  const std::string rest = text.substr(eq + 1);
  const size_t c1 = rest.find(':');
  const size_t c2 = c1 == std::string::npos ? c1 : rest.find(':', c1 + 1);
  if (c2 == std::string::npos) throw InputError(field, 0, "'" + text + "'", form);
  const ParsedQuantity from = ParseQuantity(rest.substr(0, c1), *dimension);
  const ParsedQuantity to = ParseQuantity(rest.substr(c1 + 1, c2 - c1 - 1), *dimension);
  const auto points = ParseNumber(rest.substr(c2 + 1));
  if (!from.error.empty()) throw InputError(field, 0, "'" + rest.substr(0, c1) + "'", from.error);
  if (!to.error.empty()) {
    throw InputError(field, 0, "'" + rest.substr(c1 + 1, c2 - c1 - 1) + "'", to.error);
  }
  if (!points || *points < 1 || *points != std::floor(*points) || *points > 100000) {
    throw InputError(field, 0, "'" + rest.substr(c2 + 1) + "'",
                     "POINTS must be a whole number in 1..100000");
  }
  axis.range = {from.value_si, to.value_si, static_cast<int>(*points)};
  return axis;
}

DisplayUnit SpeedUnitOfAxisOption(const std::string& text) {
  const size_t eq = text.find('='), c1 = text.find(':', eq), c2 = text.find(':', c1 + 1);
  const std::string to = c1 == std::string::npos ? std::string() : text.substr(c1 + 1, c2 - c1 - 1);
  return DisplayUnitOf(to, Dimension::kAngularSpeed);
}

void RequireVariableParameter(const GearboxSpec& spec, const std::string& parameter,
                              const std::string& field) {
  GearboxSpec probe = spec;
  try {
    SetParameter(probe, parameter, 0.0);
  } catch (const ParameterNotVariable& e) {
    throw InputError(field, 0, "'" + parameter + "'", e.reason());
  }
}

std::string ReadGearboxText(const std::string& path) {
  if (path.empty()) {
    throw InputError("", 0, "", "the file name is empty (give a gearbox .yaml file)", "\"\"");
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError("", 0, "", "is a directory, not a gearbox file (give a .yaml file)", path);
  }
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

}  // namespace gearnvh::config
