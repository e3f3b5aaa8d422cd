#include "operating_point.h"

#include <fmt/format.h>

#include <numbers>
#include <numeric>

#include "gearnvh/model/count_text.h"

namespace gearnvh::app {

nlohmann::json SummaryJson(const SolverSummary& s) {
  return {{"status", SolverStatusName(s.status)},
          {"message", s.message},
          {"mesh_cycles", s.mesh_cycles},
          {"events", s.events},
          {"drive_impacts", s.drive_impacts},
          {"back_impacts", s.back_impacts},
          {"separations", s.separations},
          {"grazing", s.grazing},
          {"events_per_cycle", s.events_per_cycle},
          {"matvecs", s.matvecs},
          {"matvec_per_cycle", s.matvec_per_cycle},
          {"fused_cycles", s.fused_cycles},
          {"run_fused_segments", s.run_fused_segments},
          {"jumped_cycles", s.jumped_cycles},
          {"contact_certified", s.contact_certified},
          {"simulated_s", s.simulated_s},
          {"wall_s", s.wall_s},
          {"real_time_ratio", s.real_time_ratio},
          {"table_bytes", s.table_bytes},
          {"spectral_fallback_systems", s.spectral_fallback_systems},
          {"spectral_max_condition", s.spectral_max_condition},
          {"trajectory_truncated", s.trajectory_truncated}};
}

std::string TeMeanNote(const TransmissionErrorStats& te, double half_backlash) {
  return fmt::format(
      "the mean includes half the backlash (b = {:.4g} µm: the TE is measured from the nominal "
      "rigid rotation and drive contact closes the gap at TE = b); from the drive-flank contact it "
      "is {:.4g} µm",
      half_backlash * 1e6, te.mean_from_contact * 1e6);
}

std::string DynamicFactorNote(const TransmissionErrorStats& te) {
  // Near zero: below a tenth of the peak force (a loaded mesh has mean ~ static force and peaks
  // of a few times that at most).
  if (te.dynamic_factor > 0.0 && te.mesh_force_mean >= 0.1 * te.mesh_force_max) return "";
  return fmt::format(
      "not meaningful here: the mean mesh force ({:.3g} N) is near zero next to its peaks ({:.3g} "
      "N), as under a drag torque; the factor max / static force is then large by construction",
      te.mesh_force_mean, te.mesh_force_max);
}

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
  TierAdequacyOptions adequacy;
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
  const RattleIndices& rattle = op.rattle;
  op.te = ComputeTransmissionErrorStats(trajectory, spec.WheelTorque() / model.geometry.wheel.base,
                                        model.half_backlash);

  const TransmissionErrorStats& te = op.te;
  nlohmann::json& doc = op.doc;
  doc["tier"] = reduced.name;
  doc["warnings"] = op.warnings;
  nlohmann::json adequacy_modes = nlohmann::json::array();
  for (const TierModeMatch& m : op.adequacy.modes) {
    adequacy_modes.push_back({{"full_hz", m.full_hz},
                              {"mesh_compliance_share", m.share},
                              {"tier_hz", m.tier_hz},
                              {"mac", m.mac},
                              {"relative_error", m.relative_error},
                              {"reproduced", m.reproduced}});
  }
  doc["tier_adequacy"] = {
      {"adequate", op.adequacy.adequate},
      {"max_frequency_hz", adequacy.max_frequency_hz},
      {"modes", adequacy_modes},
      {"adequate_tier", op.adequacy.adequate_tier
                            ? nlohmann::json(TierName(*op.adequacy.adequate_tier))
                            : nlohmann::json(nullptr)}};
  doc["method"] = SolverMethodName(solver.method);
  doc["events_method"] = EventMethodName(solver.events);
  doc["state_dim"] = tables.m;
  doc["summary"] = SummaryJson(summary);
  doc["memory_estimate"] = MemoryJson(op.memory);
  doc["te_rms"] = te.rms;
  doc["te"] = {{"mean", te.mean},
               {"mean_from_contact", te.mean_from_contact},
               {"mean_note", TeMeanNote(te, model.half_backlash)},
               {"rms", te.rms},
               {"peak_to_peak", te.peak_to_peak},
               {"max", te.max},
               {"min", te.min}};
  doc["rattle"] = {{"regime", RattleRegimeName(rattle.regime)},
                   {"drive_impacts_per_cycle", rattle.drive_impacts_per_cycle},
                   {"back_impacts_per_cycle", rattle.back_impacts_per_cycle},
                   {"drive_impacts_per_excitation_cycle", rattle.drive_impacts_per_excitation},
                   {"back_impacts_per_excitation_cycle", rattle.back_impacts_per_excitation},
                   {"impact_velocity_rms", rattle.impact_velocity_rms},
                   {"impact_energy_per_cycle", rattle.impact_energy_per_cycle},
                   {"separation_fraction", rattle.separation_fraction},
                   {"wheel_acceleration_rms", rattle.wheel_acceleration_rms},
                   {"no_backlash_acceleration_rms", rattle.no_backlash_acceleration_rms},
                   {"acceleration_ratio", rattle.acceleration_ratio}};
  doc["mesh_force"] = {{"mean", te.mesh_force_mean},
                       {"max", te.mesh_force_max},
                       {"dynamic_factor", te.dynamic_factor},
                       {"dynamic_factor_note", DynamicFactorNote(te)}};
  // Mesh harmonics, shaft orders and their sidebands of the TE over whole periods of the sources
  // (every recorded cycle when there are none).
  const long recorded = summary.trajectory_truncated ? 0 : summary.recorded_cycles;
  op.sideband_window = period > 0 ? (recorded / period) * period : 0;
  nlohmann::json sidebands = nlohmann::json::array();
  const long window = op.sideband_window;
  SidebandOptions sideband_options;
  sideband_options.shaft_order_sources = shaft_order_sources;
  sideband_options.scale = tables.half_backlash;
  if (window > 0 && summary.status == SolverStatus::kSuccess) {
    const int per_cycle = op.solver.samples_per_cycle;
    SpectrumAnalyzer analyzer(static_cast<int>(window * per_cycle));
    op.spectrum = TeSpectrum(trajectory, tables.mesh_period, per_cycle, window, analyzer);
    const AmplitudeSpectrum& spectrum = op.spectrum;
    const double pinion_hz = spec.operating.speed / (2.0 * std::numbers::pi);
    op.sidebands =
        SidebandTable(spectrum, 1.0 / tables.mesh_period, pinion_hz,
                      pinion_hz * spec.pinion.teeth / spec.wheel.teeth, sideband_options);
    for (const SidebandRow& r : op.sidebands) {
      sidebands.push_back({{"label", r.label},
                           {"frequency_hz", r.frequency_hz},
                           {"amplitude_m", r.amplitude},
                           {"db_re_1um", r.db_re_1um},
                           {"background_m", r.background}});
    }
  }
  doc["sidebands"] = sidebands;
  doc["sideband_window_cycles"] = window;
  nlohmann::json notes = nlohmann::json::array();
  if (!op.cycles_note.empty()) notes.push_back(op.cycles_note);
  if (!shaft_order_sources) {
    notes.push_back(
        "the model has no runout, pitch error or engine order: no shaft-order line or sideband "
        "can arise, so only the mesh harmonics are listed");
  }
  if (window == 0) {
    notes.push_back(
        "no spectrum: the record holds no whole period of the engine orders and gear "
        "errors");
  }
  notes.push_back(fmt::format(
      "lines are listed when {:g} dB above the median of the {} bins around them and above {:g} "
      "dB relative to the strongest bin",
      sideband_options.prominence_db, 2 * sideband_options.background_bins,
      sideband_options.rounding_floor_db));
  doc["sidebands_notes"] = notes;
  return op;
}

std::string MeshHarmonicsText(const std::vector<SidebandRow>& rows) {
  std::string text;
  for (const SidebandRow& r : rows) {
    // "1 fm = 23 fin" reads "1 fm": the lines sharing its bin are in --json.
    if (IsMeshHarmonic(r)) {
      text +=
          fmt::format("{}: {:.4f} µm  ", r.label.substr(0, r.label.find(" = ")), r.amplitude * 1e6);
    }
  }
  return text;
}

}  // namespace gearnvh::app
