// The loader's YAML walker (internal to app/config): a Reader reads typed values from a yaml-cpp
// tree, remembers the line and raw text of every path it reads, and throws InputError naming the
// path, the value as written and the rule.
#pragma once

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "source_locations.h"
#include "units.h"
#include "utf8_check.h"

namespace gearnvh::config {

inline int LineOf(const YAML::Node& n) {
  const int line = n.Mark().line;
  return line >= 0 ? line + 1 : 0;
}

inline std::string Join(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

inline std::string Describe(const YAML::Node& n) {
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
  using Location = SourceLocations::Location;

  [[noreturn]] void Fail(const std::string& path, const YAML::Node& n, const std::string& value,
                         const std::string& rule) const {
    throw InputError(path, LineOf(n), value, rule);
  }

  // Names and texts reach terminals, reports and JSON: a control character in one (entered
  // through a YAML escape) is refused rather than printed.
  void RequireNoControlCharacters(const std::string& path, const YAML::Node& n,
                                  const std::string& text) const {
    const size_t at = ControlCharacterAt(text);
    if (at == std::string::npos) return;
    Fail(path, n, "'" + text + "'",
         "must not contain control characters (character " + std::to_string(at + 1) +
             " is one, written as a YAML escape such as \\x07 or \\0): names and texts are "
             "printed on terminals and in reports");
  }

  // A name the user chose for a part (a shaft, gear or coupling) heads CSV columns
  // ("<coupling>.twist_rad") and table rows: it must not be empty, and a comma or a double quote in
  // it would split or open a field.
  void RequirePartName(const std::string& path, const YAML::Node& n,
                       const std::string& name) const {
    if (name.empty()) Fail(path, n, "''", "a name must not be empty: it heads rows and columns");
    const size_t at = name.find_first_of(",\"");
    if (at == std::string::npos) return;
    Fail(path, n, "'" + name + "'",
         std::string("a name must not contain '") + name[at] +
             "': names head the columns of the CSV files gearnvh writes");
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
      RequireNoControlCharacters(Join(path, key), kv.first, key);
      // yaml-cpp reads a merge key as an ordinary key named "<<"; say what it is.
      if (key == "<<") {
        Fail(Join(path, key), kv.first, "",
             "YAML merge keys (<<) are not supported; write the keys out");
      }
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
           "must be " + DimensionWithArticle(d) +
               (d == Dimension::kDimensionless ? "" : " such as a number with a unit"));
    }
    const ParsedQuantity q = ParseQuantity(n.Scalar(), d);
    if (!q.error.empty()) Fail(path, n, "'" + n.Scalar() + "'", q.error);
    Remember(path, n, n.Scalar());
    return q.value_si;
  }

  int Integer(const YAML::Node& map, const std::string& path, const std::string& key,
              std::optional<int> fallback = std::nullopt) {
    const YAML::Node n = Child(map, path, key, !fallback.has_value());
    if (!n.IsDefined()) return *fallback;
    const std::string p = Join(path, key);
    if (!n.IsScalar()) Fail(p, n, Describe(n), "must be an integer");
    const auto v = ParseNumber(n.Scalar());
    if (!v || std::floor(*v) != *v) Fail(p, n, "'" + n.Scalar() + "'", "must be an integer");
    if (std::abs(*v) > 2e9) {
      Fail(p, n, "'" + n.Scalar() + "'", "must be an integer between -2e9 and 2e9");
    }
    Remember(p, n, n.Scalar());
    return static_cast<int>(*v);
  }

  bool Boolean(const YAML::Node& map, const std::string& path, const std::string& key,
               bool fallback) {
    const YAML::Node n = Child(map, path, key, false);
    if (!n.IsDefined()) return fallback;
    const std::string p = Join(path, key);
    // YAML 1.2's core booleans, unquoted (a quoted "true" is a text).
    const std::string v = n.IsScalar() ? n.Scalar() : "";
    const bool yes = v == "true" || v == "True" || v == "TRUE";
    const bool no = v == "false" || v == "False" || v == "FALSE";
    if (!n.IsScalar() || n.Tag() == "!" || !(yes || no)) {
      Fail(p, n,
           !n.IsScalar()    ? Describe(n)
           : n.Tag() == "!" ? "\"" + v + "\""
                            : "'" + v + "'",
           "must be true or false (unquoted)");
    }
    Remember(p, n, v);
    return yes;
  }

  std::string String(const YAML::Node& map, const std::string& path, const std::string& key,
                     std::optional<std::string> fallback = std::nullopt) {
    const YAML::Node n = Child(map, path, key, !fallback.has_value());
    if (!n.IsDefined()) return *fallback;
    const std::string p = Join(path, key);
    if (!n.IsScalar()) Fail(p, n, Describe(n), "must be a text");
    RequireNoControlCharacters(p, n, n.Scalar());
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
    locations_.Remember(path, LineOf(n), raw);
  }

  // The location of `path`, or of its longest known prefix.
  Location Find(const std::string& path) const { return locations_.Find(path); }
  bool Exact(const std::string& path) const { return locations_.Exact(path); }

  // Everything read so far (moved out once the document is loaded).
  SourceLocations TakeLocations() { return std::move(locations_); }

 private:
  static std::string JoinList(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  }
  SourceLocations locations_;
};

// LoadGearboxFromString, also giving the locations of what was read and the note on a default
// speed sweep clipped to the pitch-line velocity limit (LoadedGearbox::sweep_note).
GearboxSpec LoadPairFromString(const std::string& text, const std::string& source,
                               SourceLocations& where, std::string& sweep_note);

// Parses YAML text (valid UTF-8 required); InputError naming `source` and the line otherwise.
YAML::Node ParseYaml(const std::string& text, const std::string& source);

// The rule a YAML syntax error `e` in `text` broke, in words ("not valid YAML: ..."): nesting too
// deep and a tab in the indentation are named as such.
std::string YamlSyntaxRule(const YAML::Exception& e, const std::string& text);

// Reads the document with `read`, validates (and completes) it with `validate`, and attributes
// every error to `source`, with range errors pointed back at the line and the value as the user
// wrote it. The locations of what was read go to `where` (for errors raised after loading).
template <typename Read, typename Validate>
auto ReadAndValidate(const YAML::Node& root, const std::string& source, Read&& read,
                     Validate&& validate, SourceLocations& where) {
  Reader reader;
  try {
    auto spec = read(reader, root);
    where = reader.TakeLocations();
    try {
      validate(spec);
    } catch (const InputError& e) {
      throw LocatedIn(e, where, source);
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

}  // namespace gearnvh::config
