// Where each YAML path of one loaded document was written: its line and the value as written.
// The loader fills it while reading; it travels with the loaded document (LoadedGearbox) so an
// error raised later by the model, the solver or a command can point back at the file.
#pragma once

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

 private:
  std::map<std::string, Location> locations_;
};

// `e` located in `source` through `where`: the line of its YAML path (or of the closest enclosing
// key written), the value as written when the path itself was written, and its lengths and angles
// in the units written at their paths (mm and deg for a path not written). An error that already
// has a line, names a command-line option ("--tier") or names another source is only attributed
// (to its own source when it has one).
inline InputError LocatedIn(const InputError& e, const SourceLocations& where,
                            const std::string& source) {
  const std::string& from = e.source().empty() ? source : e.source();
  if (e.line() > 0 || e.path().empty() || e.path().rfind("--", 0) == 0 || from != source) {
    return e.WithSource(from);
  }
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
