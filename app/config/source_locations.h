// Where each YAML path of one loaded document was written: its line and the value as written.
// The loader fills it while reading; it travels with the loaded document (LoadedGearbox) so an
// error raised later by the model, the solver or a command can point back at the file.
#pragma once

#include <cctype>
#include <map>
#include <optional>
#include <string>

#include "config/units.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::config {

class SourceLocations {
 public:
  struct Location {
    int line = 0;     // 1-based; 0 when unknown
    std::string raw;  // the value as written ("" for mappings and lists)
  };

  void Remember(const std::string& path, int line, const std::string& raw) {
    locations_[path] = Location{line, raw};
  }

  // The location of `path`, or of its longest known prefix ("a.b[2].c" -> "a.b[2]" -> "a.b").
  Location Find(std::string path) const {
    while (true) {
      if (auto it = locations_.find(path); it != locations_.end()) return it->second;
      const auto cut = path.find_last_of(".[");
      if (cut == std::string::npos) return {};
      path = path.substr(0, cut);
    }
  }

  bool Exact(const std::string& path) const { return locations_.count(path) > 0; }
  bool empty() const { return locations_.empty(); }

  // A path the model uses for one the document wrote under another name: a schema-1 gearbox runs
  // as the train TrainOf makes of it, whose errors say meshes[0].backlash for mesh.backlash.
  void Alias(const std::string& used, const std::string& written) { aliases_[used] = written; }

  // `path` as the document wrote it: its longest aliased prefix (ending at a '.' or '[') renamed.
  std::string Written(const std::string& path) const {
    for (std::string prefix = path;;) {
      if (auto it = aliases_.find(prefix); it != aliases_.end()) {
        return it->second + path.substr(prefix.size());
      }
      const auto cut = prefix.find_last_of(".[");
      if (cut == std::string::npos) return path;
      prefix.resize(cut);
    }
  }

  // `text` with every aliased path it mentions as the document wrote it ("the gear it meshes with
  // in meshes[0]" -> "... in mesh"); a mention is renamed whole, not inside a longer name.
  std::string WrittenInText(std::string text) const {
    const auto name_char = [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '[' ||
             c == ']';
    };
    for (size_t at = 0; at < text.size(); ++at) {
      if (at > 0 && name_char(text[at - 1])) continue;
      size_t end = at;
      while (end < text.size() && name_char(text[end])) ++end;
      if (end == at) continue;
      // A mention ends before a sentence's full stop.
      while (end > at && text[end - 1] == '.') --end;
      const std::string written = Written(text.substr(at, end - at));
      text.replace(at, end - at, written);
      at += written.size();
    }
    return text;
  }

  bool HasAliases() const { return !aliases_.empty(); }

 private:
  std::map<std::string, Location> locations_;
  std::map<std::string, std::string> aliases_;
};

// `error` located in `source` through `where`: named as the document wrote it (Written), at the
// line of its YAML path (or of the closest enclosing key written), with the value as written when
// the path itself was written, and its lengths and angles in the units written at their paths (mm
// and deg for a path not written). An error that already has a line, names a command-line option
// ("--tier") or names another source is only attributed (to its own source when it has one).
inline InputError LocatedIn(const InputError& error, const SourceLocations& where,
                            const std::string& source) {
  const std::string& from = error.source().empty() ? source : error.source();
  if (error.line() > 0 || error.path().empty() || error.path().rfind("--", 0) == 0 ||
      from != source) {
    return error.WithSource(from);
  }
  // Named as the document wrote it, then located there.
  const InputError e =
      where.HasAliases()
          ? error.Renamed([&where](const std::string& p) { return where.Written(p); },
                          [&where](const std::string& r) { return where.WrittenInText(r); })
          : error;
  const SourceLocations::Location loc = where.Find(e.path());
  const bool exact = where.Exact(e.path()) && !loc.raw.empty();
  const auto written_unit = [&where](const std::string& path, InputError::Dimension dimension) {
    const SourceLocations::Location at = where.Find(path);
    if (!where.Exact(path) || at.raw.empty()) return std::optional<DisplayUnit>();
    return std::optional<DisplayUnit>(
        DisplayUnitOf(at.raw, dimension == InputError::Dimension::kLength ? Dimension::kLength
                                                                          : Dimension::kAngle));
  };
  return e.Located(loc.line, exact ? "'" + loc.raw + "'" : "", from, written_unit);
}

}  // namespace gearnvh::config
