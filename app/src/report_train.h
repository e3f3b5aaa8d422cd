// One gear train (schema gearnvh/2) of a report, built into its folder: the train's check (modes
// and Campbell data of analysis.tier), the operating point on the train solver with every
// mesh's TE spectrum lines, a speed sweep, the figures (Campbell diagram; per mesh TE RMS and
// impacts per cycle against the input speed; each loose gear's impact energy against speed), the
// data files and the page (docs/reports.md, "Gear trains").
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "gearnvh/model/train_spec.h"
#include "report_gearbox.h"

namespace gearnvh::app {

// Writes everything into `folder` (which exists) and returns the summary the batch index lists.
// Throws (InputError, std::runtime_error) on failure; BuildGearboxReport reports it. The operating
// point (with its histories and results.uff) is refused, naming analysis.cycles, when its memory
// estimate exceeds `memory` (this gearbox's share; nullopt: not checked), as a pair's.
nlohmann::json BuildTrainReport(const std::string& file, const std::filesystem::path& folder,
                                const ReportCommandOptions& options, int threads,
                                const StageProgress& stage, const TrainSpec& spec,
                                const std::optional<MemoryLimit>& memory);

}  // namespace gearnvh::app
