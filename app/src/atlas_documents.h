// The pair atlas's documents: atlas.json (and `atlas --json`), atlas.csv, and the cell JSON the
// checkpoint stores and MPI ranks exchange. The axis JSON, the CSV quoting and the regime names
// are shared with the train's atlas (train_atlas_command.h) and the reports.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {

nlohmann::json AtlasAxisJson(const AtlasAxis& a);
// One cell as atlas.json lists it, and back (throws on a missing or mistyped field).
nlohmann::json AtlasCellJson(const AtlasCell& c);
AtlasCell AtlasCellFromJson(const nlohmann::json& j);

nlohmann::json AtlasJson(const AtlasResult& r, const AtlasOptions& o);

// What a pair's and a train's atlas.json say besides their axes and cells: the cells per regime
// name ("failed" counts the failed ones), the failed cells, the run's settings (`o`: AtlasOptions
// or TrainAtlasOptions, alike in these fields) and its threads and wall time.
template <typename Options>
nlohmann::json AtlasRunJson(const std::map<std::string, int>& regime_counts, int failed_cells,
                            const Options& o, int threads, double wall_s) {
  return {{"regime_counts", regime_counts},
          {"failed_cells", failed_cells},
          {"cycles_per_cell", o.cycles},
          {"transient_cycles", o.transient_cycles},
          {"chaos_threshold_per_forcing_cycle", o.chaos_threshold},
          {"method", EventMethodName(o.events)},
          {"threads", threads},
          {"wall_s", wall_s}};
}
// Parameter columns in the units of the gearbox file (header "operating.speed [rpm]").
std::string AtlasCsv(const AtlasResult& r, const GearboxSpec& spec);
// A CSV field in double quotes (quotes and newlines in `text` become single quotes).
std::string CsvQuoted(std::string text);

// The regime a results document names (RattleRegimeName); throws on a name that is none.
RattleRegime RegimeFromJson(const nlohmann::json& regime);

}  // namespace gearnvh::app
