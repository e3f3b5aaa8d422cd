// `gearnvh atlas FILE [--x P=FROM:TO:N] [--y P=FROM:TO:N] [--tier T] [--cycles N] [--transient N]
// [--jobs N] [--method M] [--out DIR] [--json]`: the chaos atlas of nvh/atlas.h over two schema
// parameters (defaults from analysis.atlas) — a regime map on the terminal, atlas.csv and
// atlas.json.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/nvh/atlas.h"

namespace gearnvh::app {

struct AtlasCommandOptions {
  std::string file;
  std::optional<std::string> x, y;  // PARAMETER=FROM:TO:POINTS
  std::optional<std::string> tier;
  std::optional<long> cycles;               // averaged mesh cycles per cell
  std::optional<long> transient;            // settling cycles per cell
  int jobs = 0;                             // threads; 0 = all cores
  LadderMethod method = LadderMethod::kV3;  // kFused locates events as kV3
  std::optional<std::string> out;
  bool json = false;
  bool resume = false;  // skip the cells already in DIR's checkpoint (needs --out)
};

// Under mpirun the cells are split across ranks (round robin), each rank runs its cells on
// threads, and rank 0 gathers them and alone writes the outputs and shows progress.
int RunAtlas(const AtlasCommandOptions& options);

// An axis given to a pair's atlas or orbit sweep outside its file (a command-line option, a Python
// argument; the loader checks the file's): a parameter SetParameter can set on `spec`, and a speed
// axis within the pitch-line velocity limit at its fastest end. InputError naming `field`.
// `text`: the axis as given.
void RequirePairAxisOption(const GearboxSpec& spec, const AtlasAxis& axis, const std::string& text,
                           const std::string& field);

// The atlas documents (also used by reports).
nlohmann::json AtlasJson(const AtlasResult& r, const AtlasOptions& o);
// Shared with the train's atlas (train_atlas_command.h):
nlohmann::json AtlasAxisJson(const AtlasAxis& a);
// '.' no impact, 'S' single-sided, 'D' double-sided, 'C' chaotic, 'X' failed.
char RegimeLetter(bool ok, RattleRegime regime);
// The regime a results document names (RattleRegimeName); throws on a name that is none.
RattleRegime RegimeFromJson(const nlohmann::json& regime);
// The legend (when asked) and the map, rows from the last y value down; letter(k) of cell
// k = iy * nx + ix.
void PrintRegimeMap(int nx, int ny, const std::function<char(int)>& letter, bool legend = true);
// A CSV field in double quotes (quotes and newlines in `text` become single quotes).
std::string CsvQuoted(std::string text);
// "atlas: 42% (5/12 cells)" on stderr when it is a terminal (and rank 0); empty otherwise.
AtlasProgress AtlasTerminalProgress(int rank, int ranks);
// The exit code of an atlas with `failed` of `total` cells failed: 1 (saying so on stderr) or 0.
int ReportFailedAtlasCells(int failed, size_t total);

// Parameter columns in the units of the gearbox file (header "operating.speed [rpm]").
std::string AtlasCsv(const AtlasResult& r, const GearboxSpec& spec);

}  // namespace gearnvh::app
