// `gearnvh whine FILE [--tier T] [--speeds N] [--harmonics H] [--sidebands S] [--jobs N]
// [--out DIR] [--json]`: the frequency-domain whine of any gearbox over analysis.speed_sweep
// (analysis/whine.h): per mesh the dynamic TE and mesh force at every line, per bearing its
// force on the housing, per shaft its speed fluctuation, and the speeds where a mesh may lose
// contact; as text, JSON (docs/cli.md, "whine") and CSV files.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/analysis/whine.h"

namespace gearnvh::app {

struct WhineCommandOptions {
  std::string file;
  std::optional<std::string> tier;
  int speeds = 2000;
  int harmonics = 3;
  int sidebands = 2;
  int jobs = 1;
  std::optional<std::string> out;
  std::optional<std::string> uff;      // UFF dataset-58 file of every mesh's TE and force tracks
  std::optional<std::string> housing;  // the housing transfer table (housing_table.h)
  bool json = false;
};

int RunWhineCommand(const WhineCommandOptions& options);

// The result as one JSON document (docs/cli.md), and its CSV files: a row per speed, mesh and
// line; a row per speed, bearing and line (docs/cli.md, "whine").
nlohmann::json WhineJson(const WhineResult& r);
std::string WhineMeshesCsv(const WhineResult& r);
std::string WhineBearingsCsv(const WhineResult& r);
// A row per speed and line: the housing point's acceleration amplitude and its level in dB re
// 1e-6 m/s^2 (empty where the line lies outside the table).
std::string WhineHousingCsv(const WhineResult& r);
// "input.bearings[0]", or "output support" for the default support of a rigid shaft.
std::string WhineBearingName(const WhineBearing& b);

}  // namespace gearnvh::app
