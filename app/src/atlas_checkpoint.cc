#include "atlas_checkpoint.h"

#include <fstream>
#include <functional>
#include <sstream>

#include "atlas_documents.h"
#include "atomic_file.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {

std::string AtlasCheckpointSettingsText(const std::string& file, const AtlasAxis& x,
                                        const AtlasAxis& y, long cycles, long transient_cycles,
                                        EventMethod events, Tier tier, double chaos_threshold) {
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string file_text = text.str();
  const nlohmann::json j = {{"file_hash", std::to_string(std::hash<std::string>{}(file_text))},
                            {"x", AtlasAxisJson(x)},
                            {"y", AtlasAxisJson(y)},
                            {"cycles", cycles},
                            {"transient", transient_cycles},
                            {"method", EventMethodName(events)},
                            {"tier", static_cast<int>(tier)},
                            {"chaos_threshold", chaos_threshold}};
  return j.dump();
}

std::vector<nlohmann::json> PrepareAtlasCheckpoint(const AtlasCheckpoint& cp, bool resume,
                                                   const AtlasCellCheck& check_cell) {
  namespace fs = std::filesystem;
  std::vector<nlohmann::json> done;
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
          nlohmann::json c = nlohmann::json::parse(line);
          check_cell(c);
          const int ix = c.at("ix").get<int>(), iy = c.at("iy").get<int>();
          if (c.at("ok").get<bool>() && ix >= 0 && iy >= 0 && ix < cp.nx && iy < cp.ny) {
            done.push_back(std::move(c));
          }
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
