// docs/gearbox-yaml.md against the loader: every key path in the reference's tables must be a key
// the loader knows. The loader rejects an unknown key at its parent mapping before it reads any
// value of that mapping, so each documented key is put into a complete valid gearbox and the
// load must not fail with "unknown key" at that path. A control run with a made-up sibling key
// must fail with "unknown key" at exactly the sibling's path, which proves the loader reached
// that mapping (otherwise the first check would pass vacuously).
#include <yaml-cpp/yaml.h>

#include <catch2/catch.hpp>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::config {
namespace {

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Backticked dotted paths in the first column of the reference's tables.
std::vector<std::string> DocumentedKeyPaths(const std::string& markdown) {
  static const std::set<std::string> roots{"schema", "name",      "materials", "gears",
                                           "mesh",   "shafts",    "operating", "analysis"};
  std::vector<std::string> out;
  std::istringstream lines(markdown);
  std::string line;
  const std::regex first_cell(R"(^\|\s*`([A-Za-z_][A-Za-z0-9_.\[\]]*)`\s*\|)");
  while (std::getline(lines, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, first_cell)) continue;
    const std::string path = m[1];
    if (roots.count(path.substr(0, path.find('.'))) != 0) out.push_back(path);
  }
  return out;
}

// Splits "shafts.input.bearings[].at" into {"shafts", "input", "bearings[]", "at"}.
std::vector<std::string> Split(const std::string& path) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream ss(path);
  while (std::getline(ss, part, '.')) parts.push_back(part);
  return parts;
}

// A copy of `base` with `key` (its last element) set under the mapping the other parts lead to;
// missing mappings are created, "name[]" steps into item 0 of a list (created when missing).
YAML::Node WithKey(const YAML::Node& base, const std::vector<std::string>& parts,
                   const std::string& key) {
  // yaml-cpp: `a = b` on nodes assigns content; reset() rebinds the handle.
  YAML::Node root = YAML::Clone(base);
  YAML::Node node;
  node.reset(root);
  for (const std::string& p : parts) {
    const bool list = p.size() > 2 && p.substr(p.size() - 2) == "[]";
    const std::string name = list ? p.substr(0, p.size() - 2) : p;
    if (list) {
      if (!node[name].IsSequence() || node[name].size() == 0) {
        YAML::Node seq(YAML::NodeType::Sequence);
        seq.push_back(YAML::Node(YAML::NodeType::Map));
        node[name] = seq;
      }
      YAML::Node item = node[name][0];
      node.reset(item);
    } else {
      if (!node[name].IsMap()) node[name] = YAML::Node(YAML::NodeType::Map);
      YAML::Node child = node[name];
      node.reset(child);
    }
  }
  // Keep a value already there (the document stays valid); otherwise any scalar: the unknown-key
  // check runs before values are read.
  if (!node[key].IsDefined()) node[key] = "1";
  return root;
}

// The loader's complaint about `doc`, or "" when it loads.
std::pair<std::string, std::string> LoadError(const YAML::Node& doc) {
  YAML::Emitter out;
  out << doc;
  try {
    (void)LoadGearboxFromString(out.c_str(), "doc");
  } catch (const InputError& e) {
    return {e.path(), e.rule()};
  }
  return {"", ""};
}

TEST_CASE("every key path in docs/gearbox-yaml.md is a key the loader knows", "[docs]") {
  const std::vector<std::string> paths =
      DocumentedKeyPaths(ReadText(std::string(GEARNVH_DOCS_DIR) + "/gearbox-yaml.md"));
  REQUIRE(paths.size() > 60);  // the tables were found (about 90 key paths)
  // A complete document to start from: the example (both shafts) plus an atlas and an excitation
  // order, so every optional mapping on the way to a key is there and valid.
  YAML::Node base = YAML::LoadFile(std::string(GEARNVH_EXAMPLES_DIR) + "/flexible_shafts.yaml");
  base["operating"]["excitation"] = YAML::Load("[{order: 2, amplitude: 100 rad/s^2}]");
  base["analysis"]["atlas"] = YAML::Load(
      "{x: {parameter: operating.speed, from: 600 rpm, to: 900 rpm, points: 2},"
      " y: {parameter: operating.torque, from: 1 N*m, to: 2 N*m, points: 2}}");
  REQUIRE(LoadError(base) == std::pair<std::string, std::string>{"", ""});
  std::set<std::string> checked;
  for (const std::string& path : paths) {
    if (!checked.insert(path).second) continue;
    INFO("documented key path " << path);
    std::vector<std::string> parts = Split(path);
    const std::string key = parts.back();
    parts.pop_back();
    YAML::Node start = YAML::Clone(base);
    // A stiffness override's parameters are read only when that model is selected.
    if (parts.size() >= 3 && parts[0] == "mesh" && parts[1] == "stiffness") {
      start["mesh"]["stiffness"]["model"] = parts[2];
    }
    const auto control = LoadError(WithKey(start, parts, "zz_not_a_key"));
    std::string parent;
    for (const std::string& p : parts) {
      parent += (parent.empty() ? "" : ".") + (p.substr(0, p.find('[')));
      if (p.find('[') != std::string::npos) parent += "[0]";
    }
    const std::string bogus_path = parent.empty() ? "zz_not_a_key" : parent + ".zz_not_a_key";
    INFO("control: " << control.first << ": " << control.second);
    REQUIRE(control.first == bogus_path);
    REQUIRE(control.second.rfind("unknown key", 0) == 0);

    const auto result = LoadError(WithKey(start, parts, key));
    const std::string full = parent.empty() ? key : parent + "." + key;
    const bool unknown = result.first == full && result.second.rfind("unknown key", 0) == 0;
    CHECK_FALSE(unknown);
  }
}

TEST_CASE("the key-path check catches a key the loader does not know", "[docs]") {
  // The same procedure on a made-up documented row must report it.
  const std::vector<std::string> paths =
      DocumentedKeyPaths("| `mesh.stiffnes_model` | text | x | y |\n| `gears.pinion.teeth` | a |\n");
  REQUIRE(paths == std::vector<std::string>{"mesh.stiffnes_model", "gears.pinion.teeth"});
  const YAML::Node base =
      YAML::LoadFile(std::string(GEARNVH_EXAMPLES_DIR) + "/flexible_shafts.yaml");
  const auto result = LoadError(WithKey(base, {"mesh"}, "stiffnes_model"));
  CHECK(result.first == "mesh.stiffnes_model");
  CHECK(result.second.rfind("unknown key", 0) == 0);
}

}  // namespace
}  // namespace gearnvh::config
