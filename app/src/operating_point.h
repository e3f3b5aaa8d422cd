// One operating point through the exact solver and the NVH signatures: what `gearnvh simulate`
// prints and what a report shows. The same gearbox without backlash (the mesh spring in permanent
// contact, acting in tension as well) is run too, for the rattle acceleration ratio.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/nvh/transmission_error.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/reduction/tier_adequacy.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/segment_tables.h"

namespace gearnvh::app {

struct OperatingPointAnalysis {
  std::string tier_name;
  std::string cycles_note;  // set when the recorded cycles were rounded to whole revolutions
  std::vector<std::string> warnings;  // the model's, the tier adequacy's, the cycles rounding's
  TierAdequacy adequacy;
  SegmentTables tables;
  SolverOptions solver;  // as run (cycles may be rounded up to whole revolutions of both gears)
  SolverResult result;
  RattleIndices rattle;
  TransmissionErrorStats te;
  long sideband_window = 0;    // mesh cycles in the spectrum (whole revolutions of both shafts)
  AmplitudeSpectrum spectrum;  // TE spectrum over that window (empty when too few cycles)
  std::vector<SidebandRow> sidebands;
  nlohmann::json doc;  // the `simulate --json` document without name and file
};

// Recording more than this many times the requested cycles (whole periods of the shaft-order
// sources, `cycles_note`) is a warning: the run takes that much longer than asked for.
constexpr long kCyclesRoundingWarningFactor = 2;

// `before_run_warning` is called with each warning about the run's cost before the run starts,
// so a command can say it on stderr at once (as TrainRunOptions::before_run_warning); empty: not
// called (the warning is in `warnings` too).
OperatingPointAnalysis AnalyseOperatingPoint(
    const GearboxSpec& spec, const ComponentModel& model, Tier tier, const SolverOptions& solver,
    const ProgressCallback& progress = {},
    const std::function<void(const std::string&)>& before_run_warning = {});

nlohmann::json SummaryJson(const SolverSummary& s);

// What the TE mean contains: half the backlash b (delta is measured from the nominal rigid
// rotation, and drive contact closes the gap at delta = b), and the mean from the contact.
std::string TeMeanNote(const TransmissionErrorStats& te, double half_backlash);

// Why the dynamic factor may not be meaningful: "" under load; a note when the mean mesh force is
// near zero next to its peaks (drag torque, rattle), where max / static force is large by
// construction.
std::string DynamicFactorNote(const TransmissionErrorStats& te);

}  // namespace gearnvh::app
