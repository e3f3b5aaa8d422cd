// The checkpoint of an atlas run (--out DIR, --resume), a pair's or a train's alike:
// DIR/.atlas-checkpoint/settings.json (what was asked; a resume with other settings is refused)
// and one cells-rank-R.jsonl per rank, one computed cell per line as atlas.json lists it (flushed
// as it completes, so a killed run loses only the cells in flight).
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "atlas_documents.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {

struct AtlasCheckpoint {
  std::filesystem::path dir;
  std::string settings;  // AtlasCheckpointSettings
  int nx = 0, ny = 0;    // the grid: a restored cell outside it (a damaged line) is recomputed
};

// What a resume must match: the gearbox file's hash (its text as read now), the axes, cycles,
// method, tier and chaos threshold (AtlasCheckpointSettings takes them from AtlasOptions or
// TrainAtlasOptions, alike in these fields).
std::string AtlasCheckpointSettingsText(const std::string& file, const AtlasAxis& x,
                                        const AtlasAxis& y, long cycles, long transient_cycles,
                                        EventMethod events, Tier tier, double chaos_threshold);
template <typename Options>
std::string AtlasCheckpointSettings(const std::string& file, const AtlasAxis& x, const AtlasAxis& y,
                                    const Options& o) {
  return AtlasCheckpointSettingsText(file, x, y, o.cycles, o.transient_cycles, o.events, o.tier,
                                     o.chaos_threshold);
}

// The checkpoint in DIR/.atlas-checkpoint of a run that writes to DIR (--out) over the axes x and
// y; none otherwise.
template <typename Options>
std::optional<AtlasCheckpoint> AtlasCheckpointIn(const std::optional<std::string>& out_dir,
                                                 const std::string& file, const AtlasAxis& x,
                                                 const AtlasAxis& y, const Options& o) {
  if (!out_dir) return std::nullopt;
  return AtlasCheckpoint{std::filesystem::path(*out_dir) / ".atlas-checkpoint",
                         AtlasCheckpointSettings(file, x, y, o), x.range.points, y.range.points};
}

// Rank 0: prepares the checkpoint and returns the cells already computed (resume), as JSON: the
// logged lines that parse, pass `check_cell` (which throws on a cell its reader cannot read), are
// ok and lie inside the grid. Any other line's cell is computed again.
using AtlasCellCheck = std::function<void(const nlohmann::json&)>;
std::vector<nlohmann::json> PrepareAtlasCheckpoint(const AtlasCheckpoint& cp, bool resume,
                                                   const AtlasCellCheck& check_cell);

}  // namespace gearnvh::app
