// The checkpoint of a pair's atlas run (--out DIR, --resume): DIR/.atlas-checkpoint/settings.json
// (what was asked; a resume with other settings is refused) and one cells-rank-R.jsonl per rank,
// one computed cell per line (flushed as it completes, so a killed run loses only the cells in
// flight).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "gearnvh/nvh/atlas.h"

namespace gearnvh::app {

struct AtlasCheckpoint {
  std::filesystem::path dir;
  std::string settings;  // AtlasCheckpointSettings
  int nx = 0, ny = 0;    // the grid: a restored cell outside it (a damaged line) is recomputed
};

// What a resume must match: the file's hash, the axes, cycles, method, tier and chaos threshold.
std::string AtlasCheckpointSettings(const std::string& file_text, const AtlasAxis& x,
                                    const AtlasAxis& y, const AtlasOptions& o);

// Rank 0: prepares the checkpoint and returns the cells already computed (resume).
std::vector<AtlasCell> PrepareAtlasCheckpoint(const AtlasCheckpoint& cp, bool resume);

}  // namespace gearnvh::app
