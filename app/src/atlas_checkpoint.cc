#include "atlas_checkpoint.h"

#include <fstream>
#include <functional>
#include <sstream>

#include "atlas_documents.h"
#include "atomic_file.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {

std::string AtlasCheckpointSettings(const std::string& file_text, const AtlasAxis& x,
                                    const AtlasAxis& y, const AtlasOptions& o) {
  const nlohmann::json j = {{"file_hash", std::to_string(std::hash<std::string>{}(file_text))},
                            {"x", AtlasAxisJson(x)},
                            {"y", AtlasAxisJson(y)},
                            {"cycles", o.cycles},
                            {"transient", o.transient_cycles},
                            {"method", EventMethodName(o.events)},
                            {"tier", static_cast<int>(o.tier)},
                            {"chaos_threshold", o.chaos_threshold}};
  return j.dump();
}

std::vector<AtlasCell> PrepareAtlasCheckpoint(const AtlasCheckpoint& cp, bool resume) {
  namespace fs = std::filesystem;
  std::vector<AtlasCell> done;
  const fs::path settings = cp.dir / "settings.json";
  if (resume && fs::exists(settings)) {
    std::ifstream in(settings);
    std::stringstream buffer;
    buffer << in.rdbuf();
    if (buffer.str() != cp.settings + "\n") {
      throw InputError("--resume", 0, cp.dir.string(),
                       "the checkpoint was made with other settings (file, axes, cycles, method "
                       "or tier); run without --resume to start over");
    }
    for (const auto& entry : fs::directory_iterator(cp.dir)) {
      if (entry.path().extension() != ".jsonl") continue;
      std::ifstream cells(entry.path());
      std::string line;
      while (std::getline(cells, line)) {
        try {
          const AtlasCell c = AtlasCellFromJson(nlohmann::json::parse(line));
          if (c.ok && c.ix >= 0 && c.iy >= 0 && c.ix < cp.nx && c.iy < cp.ny) done.push_back(c);
        } catch (const std::exception&) {
          // A line cut short by the kill (or damaged): that cell is computed again.
        }
      }
    }
    return done;
  }
  fs::remove_all(cp.dir);
  fs::create_directories(cp.dir);
  WriteFileAtomically(settings.string(), cp.settings + "\n");
  return done;
}

}  // namespace gearnvh::app
