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
#include "run_memory.h"

namespace gearnvh::app {

struct OperatingPointAnalysis {
  std::string tier_name;
  std::string cycles_note;  // set when the recorded cycles were rounded to whole revolutions
  std::vector<std::string> warnings;  // the model's, the tier adequacy's, the cycles rounding's
  TierAdequacy adequacy;
  SegmentTables tables;
  SolverOptions solver;  // as run (cycles may be rounded up to whole revolutions of both gears)
  RunMemory memory;      // estimated before the run (OperatingPointMemory)
  SolverResult result;
  RattleIndices rattle;
  TransmissionErrorStats te;
  long sideband_window = 0;    // mesh cycles in the spectrum (whole revolutions of both shafts)
  AmplitudeSpectrum spectrum;  // TE spectrum over that window (empty when too few cycles)
  std::vector<SidebandRow> sidebands;
  nlohmann::json doc;  // the `simulate --json` document without name and file
};

// The mesh harmonics of a TE sideband table on one line, as `simulate` prints them: "1 fm: 0.1234
// µm  2 fm: 0.0123 µm  " (a table holds up to hundreds of shaft-order lines and sidebands, down
// to the rounding floor: those are in --json). Empty when no harmonic stands out.
std::string MeshHarmonicsText(const std::vector<SidebandRow>& rows);

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

nlohmann::json SummaryJson(const SolverSummary& s);

// What the TE mean contains: half the backlash b (delta is measured from the nominal rigid
// rotation, and drive contact closes the gap at delta = b), and the mean from the contact.
std::string TeMeanNote(const TransmissionErrorStats& te, double half_backlash);

// Why the dynamic factor may not be meaningful: "" under load; a note when the mean mesh force is
// near zero next to its peaks (drag torque, rattle), where max / static force is large by
// construction.
std::string DynamicFactorNote(const TransmissionErrorStats& te);

}  // namespace gearnvh::app
