// The chaos atlas of a gear train (schema gearnvh/2) over two of its parameters
// (TrainParameterOf, model/spec_parameters.h): per cell a variant of the train with both set and
// validated, and its ComputeTrainAtlasPoint (nvh/train_atlas.h) — the largest Lyapunov exponent,
// each mesh's impacts and regime, each loose gear's rattle index — cells in parallel
// (ParallelFor), a failed cell kept with its message. Over MPI ranks and with a checkpoint the
// commands run it through their grid runner (app/src/atlas_grid.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/nvh/train_atlas.h"

namespace gearnvh {

struct TrainAtlasCell {
  int ix = 0, iy = 0;
  double x = 0.0, y = 0.0;  // SI
  TrainAtlasPoint point;
};

// Where a failed cell's reason goes (as FailureMessage(AtlasCell&)).
inline std::string& FailureMessage(TrainAtlasCell& cell) { return cell.point.message; }

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
// caller fills them: another MPI rank's, or restored on resume). The axes' names are the
// caller's to check first (SetTrainParameter); an invalid variant fails its cell, worded by
// options.input_error_message.
TrainAtlasResult RunTrainAtlas(const TrainSpec& base, const AtlasAxis& x, const AtlasAxis& y,
                               const TrainAtlasOptions& options, int threads,
                               const AtlasProgress& progress = {},
                               const std::vector<bool>& skip = {},
                               const TrainAtlasCellCallback& on_cell = {});

// The names of a train's meshes and of its loose gears, in file order.
std::vector<std::string> MeshNames(const TrainSpec& spec);
std::vector<std::string> LooseGearNames(const TrainSpec& spec);

}  // namespace gearnvh
