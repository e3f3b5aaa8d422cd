#include "operating_point.h"

#include <numbers>
#include <numeric>

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

OperatingPointAnalysis AnalyseOperatingPoint(const GearboxSpec& spec, const ComponentModel& model,
                                             Tier tier, const SolverOptions& solver,
                                             const ProgressCallback& progress) {
  OperatingPointAnalysis op;
  op.solver = solver;
  const ReducedModel reduced = ReduceModel(model, tier);
  op.tier_name = reduced.name;
  op.tables = BuildSegmentTables(model, reduced, spec);
  const SegmentTables& tables = op.tables;
  const auto [z0, state0] = StaticInitialState(tables);

  op.result = SimulateExact(tables, z0, state0, solver, progress);
  const SolverResult& result = op.result;
  const SolverSummary& summary = result.summary;
  const Trajectory& trajectory = result.trajectory;
  // The same gearbox without backlash, for the acceleration ratio: the same tables in permanent
  // drive contact, the mesh spring acting in tension as well (a tiny but non-zero backlash would
  // chatter at contact-loss resonances instead).
  SolverOptions linear = solver;
  linear.ignore_walls = true;
  const SolverResult reference =
      SimulateExact(tables, DriveEquilibrium(tables), ContactState::kDrive, linear);
  const double cycles_per_excitation = spec.operating.excitation.empty()
                                           ? 0.0
                                           : spec.pinion.teeth / spec.operating.excitation[0].order;
  op.rattle = ComputeRattleIndices(result, model.effective_mass, cycles_per_excitation, &reference);
  const RattleIndices& rattle = op.rattle;
  op.te = ComputeTransmissionErrorStats(
      trajectory, spec.operating.torque / model.geometry.wheel.base, model.half_backlash);

  const TransmissionErrorStats& te = op.te;
  nlohmann::json& doc = op.doc;
  doc["tier"] = reduced.name;
  doc["method"] = SolverMethodName(solver.method);
  doc["events_method"] = EventMethodName(solver.events);
  doc["state_dim"] = tables.m;
  doc["summary"] = SummaryJson(summary);
  doc["te_rms"] = te.rms;
  doc["te"] = {{"mean", te.mean}, {"rms", te.rms}, {"peak_to_peak", te.peak_to_peak}};
  doc["rattle"] = {{"regime", rattle.regime},
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
                       {"dynamic_factor", te.dynamic_factor}};
  // Mesh harmonics and shaft-order sidebands of the TE over whole revolutions of both shafts.
  const long revolution =
      std::lcm(static_cast<long>(spec.pinion.teeth), static_cast<long>(spec.wheel.teeth));
  op.sideband_window =
      summary.trajectory_truncated ? 0 : (summary.recorded_cycles / revolution) * revolution;
  nlohmann::json sidebands = nlohmann::json::array();
  const long window = op.sideband_window;
  if (window > 0 && summary.status == SolverStatus::kSuccess) {
    const int per_cycle = solver.samples_per_cycle;
    SpectrumAnalyzer analyzer(static_cast<int>(window * per_cycle));
    op.spectrum = TeSpectrum(trajectory, tables.mesh_period, per_cycle, window, analyzer);
    const AmplitudeSpectrum& spectrum = op.spectrum;
    const double pinion_hz = spec.operating.speed / (2.0 * std::numbers::pi);
    op.sidebands = SidebandTable(spectrum, 1.0 / tables.mesh_period, pinion_hz,
                                 pinion_hz * spec.pinion.teeth / spec.wheel.teeth, 3, 3);
    for (const SidebandRow& r : op.sidebands) {
      sidebands.push_back({{"label", r.label},
                           {"frequency_hz", r.frequency_hz},
                           {"amplitude_m", r.amplitude},
                           {"db_re_1m", r.db}});
    }
  }
  doc["sidebands"] = sidebands;
  doc["sideband_window_cycles"] = window;
  if (window == 0) {
    doc["sidebands_note"] = "needs at least lcm(z1, z2) = " + std::to_string(revolution) +
                            " recorded mesh cycles (whole revolutions of both shafts)";
  }
  return op;
}

}  // namespace gearnvh::app
