#include "gearbox_document.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <variant>
#include <vector>

#include "gearbox_loader.h"
#include "gearnvh/model/count_text.h"
#include "gearnvh/model/input_error.h"
#include "yaml_reader.h"

namespace gearnvh::config {
namespace {

YAML::Node Parse(const std::string& text, const std::string& source, const std::string& path) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    const int line = e.mark.line >= 0 ? e.mark.line + 1 : 0;
    throw InputError(path, line, "", config::YamlSyntaxRule(e, text), source);
  }
}

std::string Emit(const YAML::Node& root) {
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

// Block style everywhere (flow YAML and JSON come in on one line).
void MakeBlock(YAML::Node node) {
  if (node.IsMap() || node.IsSequence()) {
    node.SetStyle(YAML::EmitterStyle::Block);
    for (auto it = node.begin(); it != node.end(); ++it) MakeBlock(node.IsMap() ? it->second : *it);
  }
}

// The `schema` key as written; "gearnvh/1" when absent (the loader's default) or not a scalar.
std::string SchemaText(const YAML::Node& root) {
  const YAML::Node schema = root["schema"];
  return schema && schema.IsScalar() ? schema.Scalar() : "gearnvh/1";
}

// "operating.excitation[0].amplitude" -> operating, excitation, 0, amplitude. A step of digits
// indexes a list (also written as ".0.").
using Step = std::variant<std::string, size_t>;

// A list index written with `digits`: no list of a gearbox file has a billion entries, and a
// longer number would overflow (std::out_of_range).
size_t ListIndex(const std::string& digits, const std::string& path) {
  constexpr size_t kMaxDigits = 9;
  if (digits.size() > kMaxDigits) {
    throw InputError(path, 0, "'" + digits + "'",
                     "is not a list index: at most " + std::to_string(kMaxDigits) +
                         " digits (no list of a gearbox file has a billion entries)");
  }
  return static_cast<size_t>(std::stoul(digits));
}

std::vector<Step> ParsePath(const std::string& path) {
  const std::string rule =
      "must be a dotted schema path such as operating.torque or operating.excitation[0].amplitude";
  std::vector<Step> steps;
  size_t i = 0;
  while (i <= path.size()) {
    const size_t end = path.find_first_of(".[", i);
    const std::string key = path.substr(i, end == std::string::npos ? end : end - i);
    if (key.empty()) throw InputError(path, 0, "'" + path + "'", rule);
    const bool digits = key.find_first_not_of("0123456789") == std::string::npos;
    steps.emplace_back(digits ? Step(ListIndex(key, path)) : Step(key));
    i = end;
    while (i != std::string::npos && path[i] == '[') {
      const size_t close = path.find(']', i);
      const std::string index = close == std::string::npos ? "" : path.substr(i + 1, close - i - 1);
      if (index.empty() || index.find_first_not_of("0123456789") != std::string::npos) {
        throw InputError(path, 0, "'" + path + "'", rule);
      }
      steps.emplace_back(ListIndex(index, path));
      i = close + 1 < path.size() ? close + 1 : std::string::npos;
    }
    if (i == std::string::npos) break;
    if (path[i] != '.') throw InputError(path, 0, "'" + path + "'", rule);
    ++i;
    if (i == path.size()) throw InputError(path, 0, "'" + path + "'", rule);
  }
  return steps;
}

// The node at `steps`, rebinding (never assigning: yaml-cpp's operator= would alias nodes).
// With `create`, missing mapping keys (and null nodes on the way) become mappings.
YAML::Node Walk(YAML::Node root, const std::vector<Step>& steps, const std::string& path,
                bool create) {
  YAML::Node node;
  node.reset(root);
  for (size_t k = 0; k < steps.size(); ++k) {
    const bool last = k + 1 == steps.size();
    YAML::Node child;
    if (const size_t* index = std::get_if<size_t>(&steps[k])) {
      if (!node.IsSequence() || *index >= node.size()) {
        throw InputError(path, 0, "",
                         node.IsSequence() ? "list index out of range (the list has " +
                                                 Count(node.size(), "entry", "entries") + ")"
                                           : "indexes something that is not a list");
      }
      child.reset(node[*index]);
    } else {
      const std::string& key = std::get<std::string>(steps[k]);
      if (node.IsNull() && create) node = YAML::Node(YAML::NodeType::Map);
      if (!node.IsMap()) {
        throw InputError(path, 0, "",
                         "goes through '" + key + "' inside something that is not a mapping");
      }
      if (!node[key]) {
        if (!create) throw InputError(path, 0, "", "is not in the document");
        if (!last) node[key] = YAML::Node(YAML::NodeType::Map);
      }
      child.reset(node[key]);
    }
    node.reset(child);
  }
  return node;
}

}  // namespace

GearboxDocument GearboxDocument::FromText(const std::string& text, const std::string& source) {
  Parse(text, source, "");
  return GearboxDocument(text, source, false);
}

GearboxDocument GearboxDocument::FromFile(const std::string& path) {
  return FromText(ReadGearboxText(path), path);
}

GearboxDocument GearboxDocument::FromData(const std::string& flow_text, const std::string& source) {
  YAML::Node root = Parse(flow_text, source, "");
  MakeBlock(root);
  return GearboxDocument(Emit(root), source, false);
}

LoadedGearbox GearboxDocument::Load() const {
  return LoadAnyGearboxFromString(text_, LoadSource());
}

template <typename Assign>
LoadedGearbox GearboxDocument::Edit(const std::string& path, const Assign& assign) {
  const std::vector<Step> steps = ParsePath(path);
  YAML::Node root = Parse(text_, LoadSource(), "");
  if (!root.IsMap()) throw InputError(path, 0, "", "the document is not a mapping", source_);
  const std::string schema = SchemaText(root);
  try {
    YAML::Node target = Walk(root, steps, path, true);
    assign(target);
  } catch (const InputError& e) {
    throw e.WithSource(source_);
  }
  if (SchemaText(root) != schema) {
    // A pair's object cannot become a train's (their results differ): load the file again.
    throw InputError("schema", 0, SchemaText(root),
                     "an edit cannot change the schema (it is " + schema + ")", source_);
  }
  GearboxDocument edited(Emit(root), source_, true);
  LoadedGearbox loaded = edited.Load();
  *this = std::move(edited);
  return loaded;
}

LoadedGearbox GearboxDocument::SetScalar(const std::string& path, const std::string& value) {
  return Edit(path, [&](YAML::Node& target) { target = value; });
}

LoadedGearbox GearboxDocument::SetYaml(const std::string& path, const std::string& yaml) {
  YAML::Node value = Parse(yaml, source_, path);
  MakeBlock(value);
  return Edit(path, [&](YAML::Node& target) { target = value; });
}

std::string GearboxDocument::Get(const std::string& path) const {
  const YAML::Node root = Parse(text_, LoadSource(), "");
  try {
    const YAML::Node node = Walk(root, ParsePath(path), path, false);
    if (node.IsScalar()) return node.Scalar();
    return Emit(node);
  } catch (const InputError& e) {
    throw e.WithSource(source_);
  }
}

}  // namespace gearnvh::config
