// The page of one gearbox in a report (index.html in its folder): the gear pair and operating
// point, the dynamics, natural frequencies per modal tier, critical speeds, the sidebands, the
// atlas summary, the figures and links to the data files.
#pragma once

#include <string>
#include <vector>

#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/atlas.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh::app {

struct ReportFigure {
  std::string file, caption;
};

// What the page shows; all references outlive the call.
struct GearboxPageInput {
  const std::string& file;  // the gearbox file as given on the command line
  const GearboxSpec& spec;
  const ComponentModel& model;
  const ModalSummary& modes;  // of the full FE model
  const std::vector<ReducedModel>& tiers;
  const OperatingPointAnalysis& op;
  const SpeedSweepResult& sweep;
  const AtlasResult* atlas;  // null: no atlas
  long atlas_cycles;         // mesh cycles per atlas cell
  const std::vector<ReportFigure>& figures;
  const std::string& whine_html;  // the whine section (report_whine.h)
};

std::string GearboxPage(const GearboxPageInput& in);

}  // namespace gearnvh::app
