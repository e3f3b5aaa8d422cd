// `gearnvh atlas` on a gear train (schema gearnvh/2): per cell of two train parameters
// (config/train_parameters.h) one ComputeTrainAtlasPoint (nvh/train_atlas.h) — the largest Lyapunov
// exponent, each mesh's impacts and regime, each loose gear's rattle index — cells in parallel
// (ParallelFor), a failed cell kept with its message. A regime map per train and per mesh on the
// terminal, atlas.csv and atlas.json (docs/cli.md, docs/results.md). Over MPI ranks and with a
// checkpoint (--resume) as the pair's atlas (atlas_grid.h).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "atlas_command.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/train_atlas.h"

namespace gearnvh::app {

struct TrainAtlasCell {
  int ix = 0, iy = 0;
  double x = 0.0, y = 0.0;  // SI
  TrainAtlasPoint point;
};

struct TrainAtlasResult {
  AtlasAxis x, y;
  std::vector<std::string> mesh_names, loose_gear_names;
  std::vector<TrainAtlasCell> cells;  // row-major: iy * x.points + ix
  int threads = 1;
  double wall_s = 0.0;
  int Failed() const;
};

using TrainAtlasCellCallback = std::function<void(const TrainAtlasCell&)>;

// Every cell of the grid whose `skip` entry is false (skip may be empty: all cells) on `threads`
// threads (0: all cores); progress(done, cells to do) under a lock, and on_cell(cell) under a
// lock as each completes. Skipped cells are returned with ok = false and message "skipped" (the
// caller fills them: another MPI rank's, or restored on resume).
TrainAtlasResult RunTrainAtlas(const TrainSpec& base, const AtlasAxis& x, const AtlasAxis& y,
                               const TrainAtlasOptions& options, int threads,
                               const AtlasProgress& progress = {},
                               const std::vector<bool>& skip = {},
                               const TrainAtlasCellCallback& on_cell = {});

// One cell as atlas.json lists it, and back (throws on a missing or mistyped field): the form
// the checkpoint stores and MPI ranks exchange.
nlohmann::json TrainAtlasCellJson(const TrainAtlasCell& c);
TrainAtlasCell TrainAtlasCellFromJson(const nlohmann::json& j);

nlohmann::json TrainAtlasJson(const TrainAtlasResult& r, const TrainAtlasOptions& o);
std::string TrainAtlasCsv(const TrainAtlasResult& r);

// What `atlas` runs on a train, from its options (the command line's or the Python module's,
// `names` saying how they are named in errors): the cells' options (--cycles default 1080,
// --transient 300, tier, event method), the two axes (--x/--y or analysis.atlas; names and indices
// checked once) and the threads (--jobs). Throws InputError naming the option or key.
struct TrainAtlasPlan {
  TrainAtlasOptions atlas;
  AtlasAxis x, y;
  int jobs = 0;
  bool allow_slow = false;  // run even when the cost estimate exceeds an hour
  OptionNames names;
};
TrainAtlasPlan PlanTrainAtlas(const AtlasCommandOptions& options, const TrainSpec& spec,
                              const OptionNames& names = {});
// The atlas's run-cost check before any cell runs (CheckRunCost): every cell's transient,
// alignment and averaged cycles at the file's operating point (the axes' own values are not
// built; the tangent column's extra work is not counted), over the threads. Returns the warning
// (empty when none); throws InputError naming names("allow-slow") when refused.
std::string CheckTrainAtlasCost(const TrainSpec& spec, const TrainAtlasPlan& plan);
// `atlas --json` on a train: TrainAtlasJson with the train's name, `file` and the tier.
nlohmann::json TrainAtlasDocument(const TrainAtlasResult& r, const TrainAtlasOptions& o,
                                  const TrainSpec& spec, const std::string& file);

int AtlasTrain(const AtlasCommandOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
