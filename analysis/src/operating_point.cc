#include "gearnvh/analysis/operating_point.h"

#include <fmt/format.h>

#include <numbers>
#include <numeric>

#include "gearnvh/model/count_text.h"

namespace gearnvh {

RunMemory OperatingPointMemory(const SolverOptions& run, const SolverOptions& reference,
                               long spectrum_cycles) {
  const RecordingReserve recorded = PlanRecording(run);
  return {{{"recorded samples", recorded.sample_bytes()},
           {"event log", recorded.event_bytes()},
           {"backlash-free reference", PlanRecording(reference).bytes()},
           {"TE spectrum", SpectrumBytes(spectrum_cycles * run.samples_per_cycle)}},
          recorded.samples};
}

OperatingPointAnalysis AnalyseOperatingPoint(
    const GearboxSpec& spec, const ComponentModel& model, Tier tier, const SolverOptions& solver,
    const ProgressCallback& progress,
    const std::function<void(const std::string&)>& before_run_warning,
    const std::function<std::string(RunMemory&)>& before_run_memory) {
  OperatingPointAnalysis op;
  op.solver = solver;
  const ReducedModel reduced = ReduceModel(model, tier);
  op.tier_name = reduced.name;
  // Warnings the engineer must see with the numbers: the model's (fits used outside their range,
  // errors that can unload pairs) and whether the tier reproduces the modes the mesh excites.
  op.warnings = model.warnings;
  TierAdequacyOptions& adequacy = op.adequacy_options;
  adequacy.max_frequency_hz =
      3.0 * spec.pinion.teeth * spec.operating.speed / (2.0 * std::numbers::pi);
  op.adequacy = AssessTierAdequacy(model, reduced, FullModelMeshModes(model, adequacy), adequacy);
  if (!op.adequacy.adequate) op.warnings.push_back(op.adequacy.Warning());
  op.tables = BuildSegmentTables(model, reduced, spec, solver.cancel);
  const SegmentTables& tables = op.tables;
  // Shaft-order lines (runout, pitch errors, engine orders) sit on spectrum bins only over whole
  // periods of what makes them: the record is rounded up to a multiple of the model's common
  // period when that fits the sample storage, and a note says so (or what would be needed).
  const bool shaft_order_sources = model.errors.active() || !spec.operating.excitation.empty();
  const long max_cycles = op.solver.max_trajectory_samples / op.solver.samples_per_cycle;
  const long period = shaft_order_sources ? tables.CommonPeriodCycles(max_cycles) : 1;
  if (period == 0) {
    op.cycles_note =
        "shaft-order lines need whole periods of the engine orders and of the gears' errors: "
        "none within the " +
        std::to_string(max_cycles) + " cycles the sample storage holds";
  } else if (op.solver.cycles % period != 0) {
    const long rounded = (op.solver.cycles / period + 1) * period;
    if (rounded <= max_cycles) {
      op.cycles_note = "recorded " + std::to_string(rounded) + " mesh cycles instead of " +
                       std::to_string(op.solver.cycles) + ": whole periods (" +
                       std::to_string(period) +
                       " cycles) of the engine orders and gear errors for the shaft-order lines";
      if (rounded > kCyclesRoundingWarningFactor * op.solver.cycles) {
        const std::string warning = fmt::format(
            "recording {} mesh cycles, {:.0f}x the {} requested: the shaft-order lines need whole "
            "periods ({}) of the engine orders and gear errors",
            rounded, static_cast<double>(rounded) / static_cast<double>(op.solver.cycles),
            op.solver.cycles, Count(period, "cycle", "cycles"));
        op.warnings.push_back(warning);
        if (before_run_warning) before_run_warning(warning);
      }
      op.solver.cycles = rounded;
    } else {
      op.cycles_note = "shaft-order lines need a multiple of " + std::to_string(period) +
                       " recorded mesh cycles, more than the sample storage holds";
    }
  }
  // The same gearbox without backlash, for the acceleration ratio: the same tables in permanent
  // drive contact, the mesh spring acting in tension as well (a tiny but non-zero backlash would
  // chatter at contact-loss resonances instead). Only its statistics are used: no samples or
  // event log are kept.
  SolverOptions linear = op.solver;
  linear.ignore_walls = true;
  linear.max_trajectory_samples = 0;
  linear.max_logged_events = 0;
  const bool samples_fit =
      op.solver.cycles * op.solver.samples_per_cycle <= op.solver.max_trajectory_samples;
  op.memory = OperatingPointMemory(
      op.solver, linear, period > 0 && samples_fit ? op.solver.cycles / period * period : 0);
  if (before_run_memory) {
    if (const std::string warning = before_run_memory(op.memory); !warning.empty()) {
      op.warnings.push_back(warning);
      if (before_run_warning) before_run_warning(warning);
    }
  }
  const auto [z0, state0] = StaticInitialState(tables);

  op.result = SimulateExact(tables, z0, state0, op.solver, progress);
  const SolverResult& result = op.result;
  const SolverSummary& summary = result.summary;
  const Trajectory& trajectory = result.trajectory;
  const SolverResult reference =
      SimulateExact(tables, DriveEquilibrium(tables), ContactState::kDrive, linear);
  const double cycles_per_excitation = spec.operating.excitation.empty()
                                           ? 0.0
                                           : spec.pinion.teeth / spec.operating.excitation[0].order;
  op.rattle = ComputeRattleIndices(result, model.effective_mass, cycles_per_excitation, &reference);
  op.te = ComputeTransmissionErrorStats(trajectory, spec.WheelTorque() / model.geometry.wheel.base,
                                        model.half_backlash);

  // Mesh harmonics, shaft orders and their sidebands of the TE over whole periods of the sources
  // (every recorded cycle when there are none).
  const long recorded = summary.trajectory_truncated ? 0 : summary.recorded_cycles;
  op.sideband_window = period > 0 ? (recorded / period) * period : 0;
  const long window = op.sideband_window;
  op.sideband_options.shaft_order_sources = shaft_order_sources;
  op.sideband_options.scale = tables.half_backlash;
  if (window > 0 && summary.status == SolverStatus::kSuccess) {
    const int per_cycle = op.solver.samples_per_cycle;
    SpectrumAnalyzer analyzer(static_cast<int>(window * per_cycle));
    op.spectrum = TeSpectrum(trajectory, tables.mesh_period, per_cycle, window, analyzer);
    const double pinion_hz = spec.operating.speed / (2.0 * std::numbers::pi);
    op.sidebands =
        SidebandTable(op.spectrum, 1.0 / tables.mesh_period, pinion_hz,
                      pinion_hz * spec.pinion.teeth / spec.wheel.teeth, op.sideband_options);
  }
  if (!op.cycles_note.empty()) op.sideband_notes.push_back(op.cycles_note);
  if (!shaft_order_sources) {
    op.sideband_notes.push_back(
        "the model has no runout, pitch error or engine order: no shaft-order line or sideband "
        "can arise, so only the mesh harmonics are listed");
  }
  if (window == 0) {
    op.sideband_notes.push_back(
        "no spectrum: the record holds no whole period of the engine orders and gear "
        "errors");
  }
  op.sideband_notes.push_back(SidebandListingNote(op.sideband_options));
  return op;
}

std::string SidebandListingNote(const SidebandOptions& o) {
  return fmt::format(
      "lines are listed when {:g} dB above the median of the {} bins around them and above {:g} "
      "dB relative to the strongest bin",
      o.prominence_db, 2 * o.background_bins, o.rounding_floor_db);
}

}  // namespace gearnvh
