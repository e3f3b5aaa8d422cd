#include "result_documents.h"

#include <fmt/format.h>

namespace gearnvh::app {

nlohmann::json MemoryJson(const RunMemory& memory) {
  nlohmann::json parts = nlohmann::json::object();
  for (const MemoryPart& p : memory.parts) parts[p.name] = p.bytes;
  return {{"bytes", memory.bytes()}, {"parts", parts}};
}

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

nlohmann::json TierAdequacyJson(const TierAdequacy& adequacy, const TierAdequacyOptions& options,
                                const std::vector<std::string>& mesh_names) {
  nlohmann::json modes = nlohmann::json::array();
  for (const TierModeMatch& m : adequacy.modes) {
    nlohmann::json mode = {
        {"full_hz", m.full_hz}, {"mesh_compliance_share", m.share},   {"tier_hz", m.tier_hz},
        {"mac", m.mac},         {"relative_error", m.relative_error}, {"reproduced", m.reproduced}};
    if (static_cast<size_t>(m.mesh) < mesh_names.size()) {
      mode["mesh"] = mesh_names[static_cast<size_t>(m.mesh)];
    }
    modes.push_back(mode);
  }
  return {
      {"adequate", adequacy.adequate},
      {"complete", adequacy.complete},
      {"max_frequency_hz", options.max_frequency_hz},
      {"modes", modes},
      {"adequate_tier", adequacy.adequate_tier ? nlohmann::json(TierName(*adequacy.adequate_tier))
                                               : nlohmann::json(nullptr)}};
}

nlohmann::json OperatingPointJson(const OperatingPointAnalysis& op) {
  const TransmissionErrorStats& te = op.te;
  const RattleIndices& rattle = op.rattle;
  nlohmann::json doc;
  doc["tier"] = op.tier_name;
  doc["warnings"] = op.warnings;
  doc["tier_adequacy"] = TierAdequacyJson(op.adequacy, op.adequacy_options, {});
  doc["method"] = SolverMethodName(op.solver.method);
  doc["events_method"] = EventMethodName(op.solver.events);
  doc["state_dim"] = op.tables.m;
  doc["summary"] = SummaryJson(op.result.summary);
  doc["memory_estimate"] = MemoryJson(op.memory);
  doc["te_rms"] = te.rms;
  doc["te"] = {{"mean", te.mean},
               {"mean_from_contact", te.mean_from_contact},
               {"mean_note", TeMeanNote(te, op.tables.half_backlash)},
               {"rms", te.rms},
               {"peak_to_peak", te.peak_to_peak},
               {"max", te.max},
               {"min", te.min}};
  doc["rattle"] = {{"regime", RattleRegimeName(rattle.regime)},
                   {"drive_impacts_per_cycle", rattle.drive_impacts_per_cycle},
                   {"back_impacts_per_cycle", rattle.back_impacts_per_cycle},
                   {"drive_impacts_per_excitation_cycle", rattle.drive_impacts_per_excitation},
                   {"back_impacts_per_excitation_cycle", rattle.back_impacts_per_excitation},
                   {"drive_impacts_per_second", rattle.drive_impacts_per_second},
                   {"back_impacts_per_second", rattle.back_impacts_per_second},
                   {"impact_velocity_rms", rattle.impact_velocity_rms},
                   {"impact_velocity_max", rattle.impact_velocity_max},
                   {"impact_energy_per_cycle", rattle.impact_energy_per_cycle},
                   {"impact_energy_per_second", rattle.impact_energy_per_second},
                   {"separation_fraction", rattle.separation_fraction},
                   {"wheel_acceleration_rms", rattle.wheel_acceleration_rms},
                   {"no_backlash_acceleration_rms", rattle.no_backlash_acceleration_rms},
                   {"acceleration_ratio", rattle.acceleration_ratio}};
  doc["mesh_force"] = {{"mean", te.mesh_force_mean},
                       {"max", te.mesh_force_max},
                       {"dynamic_factor", te.dynamic_factor},
                       {"dynamic_factor_note", DynamicFactorNote(te)}};
  doc["sidebands"] = SidebandsJson(op.sidebands);
  doc["sideband_window_cycles"] = op.sideband_window;
  doc["sidebands_notes"] = op.sideband_notes;
  return doc;
}

nlohmann::json SidebandsJson(const std::vector<SidebandRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const SidebandRow& r : rows) {
    out.push_back({{"label", r.label},
                   {"frequency_hz", r.frequency_hz},
                   {"amplitude_m", r.amplitude},
                   {"db_re_1um", r.db_re_1um},
                   {"background_m", r.background}});
  }
  return out;
}

nlohmann::json TrainMeshesJson(const TrainOperatingPoint& op) {
  const TrainStatistics& stats = op.stats;
  const TrainTables& tables = op.tables;
  nlohmann::json meshes = nlohmann::json::array();
  for (size_t i = 0; i < stats.meshes.size(); ++i) {
    const TrainMeshStatistics& m = stats.meshes[i];
    const double mesh_cycles = stats.recorded_time / tables.meshes[i].period;
    nlohmann::json mesh = {
        {"name", m.name},
        {"mesh_period_s", tables.meshes[i].period},
        {"te",
         {{"mean", m.te_mean},
          {"rms", m.te_rms},
          {"peak_to_peak", m.te_peak_to_peak},
          {"half_backlash", tables.meshes[i].half_backlash}}},
        {"mesh_force", {{"mean", m.force_mean}, {"max", m.force_max}}},
        {"rattle",
         {{"drive_impacts", m.drive_impacts},
          {"back_impacts", m.back_impacts},
          {"separations", m.separations},
          {"grazing", m.grazing},
          {"drive_impacts_per_cycle", mesh_cycles > 0 ? m.drive_impacts / mesh_cycles : 0.0},
          {"back_impacts_per_cycle", mesh_cycles > 0 ? m.back_impacts / mesh_cycles : 0.0},
          {"separation_fraction", m.free_time_fraction},
          {"impact_velocity_rms", m.impact_velocity_rms},
          {"impact_velocity_max", m.impact_velocity_max}}}};
    if (i < op.sidebands.size()) {
      mesh["sidebands"] = SidebandsJson(op.sidebands[i].rows);
      mesh["sideband_window_cycles"] = op.sidebands[i].window_cycles;
    }
    meshes.push_back(mesh);
  }
  return meshes;
}

std::string BearingName(const std::string& shaft, int index) {
  return index >= 0 ? shaft + ".bearings[" + std::to_string(index) + "]" : shaft + " support";
}

nlohmann::json TrainBearingForcesJson(const TrainOperatingPoint& op, const TrainSpec& spec) {
  const auto xyz = [](const std::array<double, 3>& v) {
    return nlohmann::json{{"x", v[0]}, {"y", v[1]}, {"z", v[2]}};
  };
  nlohmann::json bearings = nlohmann::json::array();
  for (const TrainBearingForce& f : op.bearing_forces) {
    const std::string& shaft = spec.shafts[static_cast<size_t>(f.bearing.shaft)].name;
    nlohmann::json lines = nlohmann::json::array();
    for (const TrainBearingForce::Line& l : f.lines) {
      lines.push_back({{"label", l.label},
                       {"frequency_hz", l.frequency_hz},
                       {"amplitude_n", xyz(l.amplitude)}});
    }
    bearings.push_back({{"name", BearingName(shaft, f.bearing.index)},
                        {"shaft", shaft},
                        {"index", f.bearing.index},
                        {"at_m", f.bearing.at},
                        {"force_mean_n", xyz(f.mean)},
                        {"force_rms_n", xyz(f.rms)},
                        {"force_min_n", xyz(f.min)},
                        {"force_max_n", xyz(f.max)},
                        {"lines", lines}});
  }
  return bearings;
}

nlohmann::json TrainCouplingsJson(const std::vector<TrainCouplingResponse>& couplings,
                                  double recorded_s) {
  nlohmann::json out = nlohmann::json::array();
  const auto summary = [](const TrainOutputSummary& s) {
    return nlohmann::json{{"mean", s.mean}, {"rms", s.rms}, {"min", s.min}, {"max", s.max}};
  };
  for (const TrainCouplingResponse& c : couplings) {
    nlohmann::json stages = nlohmann::json::array();
    for (const TrainCouplingStageStatistics& s : c.stages) {
      stages.push_back({{"stage", s.stage},
                        {"entries", s.entries},
                        {"positive_entries", s.positive_entries},
                        {"negative_entries", s.negative_entries},
                        {"entries_per_second",
                         recorded_s > 0.0 ? static_cast<double>(s.entries) / recorded_s : 0.0},
                        {"engaged_fraction", s.engaged_fraction}});
    }
    out.push_back({{"name", c.name},
                   {"twist_rad", summary(c.twist)},
                   {"torque_n_m", summary(c.torque)},
                   {"stages", stages}});
  }
  return out;
}

nlohmann::json TrainLooseGearsJson(const std::vector<TrainLooseGearStatistics>& gears) {
  nlohmann::json loose = nlohmann::json::array();
  for (const TrainLooseGearStatistics& g : gears) {
    loose.push_back({{"name", g.name},
                     {"rank", g.rank},
                     {"impact_energy_per_second", g.impact_energy_per_second},
                     {"impacts", g.impacts},
                     {"drive_impacts_per_second", g.drive_impacts_per_second},
                     {"back_impacts_per_second", g.back_impacts_per_second},
                     {"impact_velocity_rms", g.impact_velocity_rms},
                     {"impact_velocity_max", g.impact_velocity_max},
                     {"rattle_index", g.rattle_index}});
  }
  return loose;
}

}  // namespace gearnvh::app
