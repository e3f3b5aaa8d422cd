// The report's whine section for any gearbox (a pair is its one-mesh train): the frequency-domain
// whine (analysis/whine.h) at the report's tier over 1000 speeds of analysis.speed_sweep, drawn
// (whine_te.png: each mesh's TE at its 1x and 2x mesh order; whine_bearings.png: each bearing's
// dynamic force on the housing), written (whine.json, whine_meshes.csv, whine_bearings.csv) and
// summarised for results.json and the page.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gearnvh/model/train_spec.h"
#include "gearnvh/render/plots.h"
#include "report_page.h"

namespace gearnvh::app {

struct WhineReport {
  std::vector<ReportFigure> figures;  // drawn into the folder
  nlohmann::json summary;             // results.json's "whine"
  std::string html;                   // the page's section
};

inline constexpr int kReportWhineSpeeds = 1000;

WhineReport BuildWhineReport(const TrainSpec& spec, Tier tier, int threads,
                             const std::filesystem::path& folder,
                             const render::ImageOptions& image);

}  // namespace gearnvh::app
