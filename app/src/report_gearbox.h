// One gearbox of a report, built into its folder: the model, the operating point, the speed
// sweep and (optionally) a coarse chaos atlas; the images, CSV, UFF, results.json and its page
// (report_page.h); and the summary the batch index lists.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/render/plots.h"
#include "report_command.h"

namespace gearnvh::app {

struct GearboxEntry {
  std::string file, folder, name;
  bool ok = false;
  bool internal = false;      // failed by a bug (exit 3), not by its input
  bool earlier_kept = false;  // failed now; DIR keeps this folder from an earlier run
  bool from_earlier = false;  // not in this run; kept from an earlier run into DIR
  std::string error;
  std::string io_reason;  // failed writing its files, for this reason ("No space left on device")
  nlohmann::json summary;
  double wall_s = 0.0;
};

// A figure that was not drawn: IoError (with the system's reason) when its file could not be
// written, else std::runtime_error; both name the image.
void ThrowUnlessDrawn(const std::string& name, const render::RenderStatus& status);

// Reports the stage a gearbox is in ("speed sweep 12/56 speeds"); empty: silent.
using StageProgress = std::function<void(const std::string&)>;

// Everything for one gearbox, written into `folder` with `threads` threads. Never throws: a
// failure is reported in the entry (ok = false, error; internal for a bug). A pair's operating
// point is refused (a failed gearbox naming analysis.cycles) when its memory estimate exceeds
// `memory` (this gearbox's share of the limit; nullopt: not checked), and warned about near it.
GearboxEntry BuildGearboxReport(const std::string& file, const std::filesystem::path& folder,
                                const ReportCommandOptions& options, int threads,
                                const StageProgress& stage,
                                const std::optional<MemoryLimit>& memory = std::nullopt);

}  // namespace gearnvh::app
