// One operating point through the exact solver and the NVH signatures: what `gearnvh simulate`
// prints and what a report shows. The same gearbox without backlash (the mesh spring in permanent
// contact, acting in tension as well) is run too, for the rattle acceleration ratio.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/model/component_model.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/nvh/transmission_error.h"
#include "gearnvh/reduction/reduced_model.h"
#include "gearnvh/reduction/tier_adequacy.h"
#include "gearnvh/solver/exact_solver.h"
#include "gearnvh/solver/segment_tables.h"

namespace gearnvh {

struct OperatingPointAnalysis {
  std::string tier_name;
  std::string cycles_note;  // set when the recorded cycles were rounded to whole revolutions
  std::vector<std::string> warnings;  // the model's, the tier adequacy's, the cycles rounding's
  TierAdequacyOptions adequacy_options;
  TierAdequacy adequacy;
  SegmentTables tables;
  SolverOptions solver;  // as run (cycles may be rounded up to whole revolutions of both gears)
  RunMemory memory;      // estimated before the run (OperatingPointMemory)
  SolverResult result;
  RattleIndices rattle;
  TransmissionErrorStats te;
  long sideband_window = 0;    // mesh cycles in the spectrum (whole revolutions of both shafts)
  AmplitudeSpectrum spectrum;  // TE spectrum over that window (empty when too few cycles)
  SidebandOptions sideband_options;
  std::vector<SidebandRow> sidebands;
  std::vector<std::string> sideband_notes;  // what the listing holds and why (cycles_note first)
};

// The rule a sideband listing follows, in words (the last of the listing's notes).
std::string SidebandListingNote(const SidebandOptions& options);

// Recording more than this many times the requested cycles (whole periods of the shaft-order
// sources, `cycles_note`) is a warning: the run takes that much longer than asked for.
constexpr long kCyclesRoundingWarningFactor = 2;

// The memory AnalyseOperatingPoint holds for the parts that grow with the recorded cycles: the
// recording of `run` (the cycles as run) and of the backlash-free `reference` (PlanRecording), and
// the TE spectrum over `spectrum_cycles` (0: none).
RunMemory OperatingPointMemory(const SolverOptions& run, const SolverOptions& reference,
                               long spectrum_cycles);

// `before_run_warning` is called with each warning about the run's cost before the run starts,
// so a command can say it on stderr at once (as TrainRunOptions::before_run_warning); empty: not
// called (the warning is in `warnings` too). `before_run_memory` gets the memory estimate before
// the run (the cycles rounded): it may add the command's own parts, throw to refuse the run, or
// return a warning (kept in `warnings` and passed to `before_run_warning`); empty: no check.
OperatingPointAnalysis AnalyseOperatingPoint(
    const GearboxSpec& spec, const ComponentModel& model, Tier tier, const SolverOptions& solver,
    const ProgressCallback& progress = {},
    const std::function<void(const std::string&)>& before_run_warning = {},
    const std::function<std::string(RunMemory&)>& before_run_memory = {});

}  // namespace gearnvh
