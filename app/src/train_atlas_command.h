// `gearnvh atlas` on a gear train (schema gearnvh/2): the options checked and planned, the cells
// run (RunTrainAtlas, gearnvh/analysis/train_atlas.h), a regime map per train and per mesh on the
// terminal, atlas.csv and atlas.json (docs/cli.md, docs/results.md). Over MPI ranks and with a
// checkpoint (--resume) as the pair's atlas (atlas_grid.h).
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "atlas_command.h"
#include "gearnvh/analysis/train_atlas.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_spec.h"
#include "gearnvh/nvh/train_atlas.h"

namespace gearnvh::app {

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
// built; the tangent column's extra work is not counted), over the threads, for one of `ranks`
// processes sharing the cells round robin (ceil(cells / ranks) cells; cells a resume restores
// are counted, so the estimate errs long). Returns the warning
// (empty when none); throws InputError naming names("allow-slow") when refused.
std::string CheckTrainAtlasCost(const TrainSpec& spec, const TrainAtlasPlan& plan, int ranks = 1);
// `atlas --json` on a train: TrainAtlasJson with the train's name, `file`, the tier, the MPI
// ranks that ran it and the cells a resume restored.
nlohmann::json TrainAtlasDocument(const TrainAtlasResult& r, const TrainAtlasOptions& o,
                                  const TrainSpec& spec, const std::string& file, int ranks = 1,
                                  size_t restored_cells = 0);

int AtlasTrain(const AtlasCommandOptions& options, const TrainSpec& spec);

}  // namespace gearnvh::app
