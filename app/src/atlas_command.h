// `gearnvh atlas FILE [--x P=FROM:TO:N] [--y P=FROM:TO:N] [--tier T] [--cycles N] [--transient N]
// [--jobs N] [--method M] [--out DIR] [--json]`: the chaos atlas of nvh/atlas.h over two schema
// parameters (defaults from analysis.atlas) — a regime map on the terminal, atlas.csv and
// atlas.json.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/nvh/atlas.h"

namespace gearnvh::app {

struct AtlasCommandOptions {
  std::string file;
  std::optional<std::string> x, y;  // PARAMETER=FROM:TO:POINTS
  std::optional<std::string> tier;
  std::optional<long> cycles;     // averaged mesh cycles per cell
  std::optional<long> transient;  // settling cycles per cell
  int jobs = 0;                   // threads; 0 = all cores
  std::string method = "v3";
  std::optional<std::string> out;
  bool json = false;
  bool resume = false;  // skip the cells already in DIR's checkpoint (needs --out)
};

// Under mpirun the cells are split across ranks (round robin), each rank runs its cells on
// threads, and rank 0 gathers them and alone writes the outputs and shows progress.
int RunAtlas(const AtlasCommandOptions& options);

// The atlas documents (also used by reports).
nlohmann::json AtlasJson(const AtlasResult& r, const AtlasOptions& o);
// Parameter columns in the units of the gearbox file (header "operating.speed [rpm]").
std::string AtlasCsv(const AtlasResult& r, const GearboxSpec& spec);

}  // namespace gearnvh::app
