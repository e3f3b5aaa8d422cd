// `gearnvh atlas FILE [--x P=FROM:TO:N] [--y P=FROM:TO:N] [--tier T] [--cycles N] [--transient N]
// [--jobs N] [--method M] [--out DIR] [--json]`: the chaos atlas of nvh/atlas.h over two schema
// parameters (defaults from analysis.atlas) — a regime map on the terminal, atlas.csv and
// atlas.json (atlas_documents.h, atlas_terminal.h; the checkpoint in atlas_checkpoint.h). A train
// file goes to train_atlas_command.h.
#pragma once

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
  bool resume = false;      // skip the cells already in DIR's checkpoint (needs --out)
  bool allow_slow = false;  // gear trains: run even when the cost estimate exceeds an hour
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

// An atlas axis given outside the file (pair or train, command line or Python) keeps the range
// rules of the file's analysis.atlas axes (FirstSweepRangeViolation: at least 2 points, FROM
// below TO, a positive FROM on a log axis). InputError naming `field` with `text`.
void RequireAtlasAxisRange(const AtlasAxis& axis, const std::string& text,
                           const std::string& field);

}  // namespace gearnvh::app
