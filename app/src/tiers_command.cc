#include "tiers_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "check_command.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/nvh/lyapunov.h"
#include "output_folder.h"
#include "train_tiers.h"
#ifdef GEARNVH_HAVE_RENDER
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/render/plots.h"
#include "report_sweep_figures.h"
#include "train_command_options.h"
#endif

namespace gearnvh::app {

namespace {

double ClosestRelativeError(double f, const std::vector<double>& reference) {
  double best = std::numeric_limits<double>::infinity();
  for (double r : reference) best = std::min(best, std::abs(f - r) / r);
  return best;
}

TierRow RunTier(const GearboxSpec& spec, const ComponentModel& model, const ReducedModel& reduced,
                const ModalSummary& full, const SolverOptions& solver, const std::string& label,
                const std::function<std::string(RunMemory&)>& before_run_memory) {
  TierRow row;
  row.name = label;
  row.method = solver.method;
  row.dof = reduced.dof;
  row.rigid_body_modes = reduced.rigid_body_modes;
  row.compliance_error = ComplianceErrorVsFull(reduced.tier, reduced.compliance_error_vs_full);
  for (size_t k = 0; k < reduced.natural_frequencies_hz.size() && k < 6; ++k) {
    const double f = reduced.natural_frequencies_hz[k];
    row.frequencies_hz.push_back(f);
    row.frequency_errors.push_back(ClosestRelativeError(f, full.frequencies_hz));
  }
  row.max_frequency_error = TierFrequencyError(reduced, full);
  const OperatingPointAnalysis op =
      AnalyseOperatingPoint(spec, model, reduced.tier, solver, {}, {}, before_run_memory);
  const SolverSummary& s = op.result.summary;
  row.state_dim = op.tables.m;
  row.table_bytes = s.table_bytes;
  if (s.status != SolverStatus::kSuccess) {
    row.status = s.status;
    row.message = s.message;
    row.te_rms = row.rattle_index = kNoResult;
    row.matvec_per_cycle = row.us_per_cycle = row.real_time_ratio = kNoResult;
    return row;
  }
  row.te_rms = op.te.rms;
  // Rattle index as in the atlas: impact energy per forcing cycle.
  row.rattle_index =
      op.rattle.impact_energy_per_cycle * ForcingPeriod(op.tables) / op.tables.mesh_period;
  row.regime = op.rattle.regime;
  row.matvec_per_cycle = s.matvec_per_cycle;
  row.us_per_cycle = 1e6 * s.wall_s / static_cast<double>(std::max<long>(1, s.mesh_cycles));
  row.real_time_ratio = s.real_time_ratio;
  return row;
}

nlohmann::json TierRowJson(const TierRow& r) {
  return {{"name", r.name},
          {"method", SolverMethodName(r.method)},
          {"status", SolverStatusName(r.status)},
          {"message", r.message},
          {"dof", r.dof},
          {"state_dim", r.state_dim},
          {"rigid_body_modes", r.rigid_body_modes},
          {"frequencies_hz", r.frequencies_hz},
          {"frequency_errors", r.frequency_errors},
          {"max_frequency_error", r.max_frequency_error},
          {"static_compliance_error", ComplianceErrorJson(r.compliance_error)},
          {"te_rms_m", ResultOrNull(r.ok(), r.te_rms)},
          {"te_rms_difference_to_finest", FiniteOrNull(r.te_rms_difference)},
          {"rattle_index_j", ResultOrNull(r.ok(), r.rattle_index)},
          {"rattle_index_difference_to_finest", FiniteOrNull(r.rattle_index_difference)},
          {"regime", r.ok() ? nlohmann::json(RattleRegimeName(r.regime)) : nlohmann::json()},
          {"matvec_per_cycle", ResultOrNull(r.ok(), r.matvec_per_cycle)},
          {"us_per_cycle", ResultOrNull(r.ok(), r.us_per_cycle)},
          {"real_time_ratio", ResultOrNull(r.ok(), r.real_time_ratio)},
          {"table_bytes", r.table_bytes}};
}

// The differences of every row to the finest (succeeded, most DOF); NaN for a failed row.
void CompareToFinest(TiersComparison& out) {
  std::vector<TierRow>& rows = out.rows;
  out.finest = FinestRow(rows);
  const TierRow& reference = rows[out.finest];
  for (TierRow& r : rows) {
    out.failed += r.ok() ? 0 : 1;
    if (!r.ok() || !reference.ok()) {
      r.te_rms_difference = r.rattle_index_difference = kNoResult;
      continue;
    }
    r.te_rms_difference = RelativeDifference(r.te_rms, reference.te_rms, kTeResolution);
    r.rattle_index_difference =
        RelativeDifference(r.rattle_index, reference.rattle_index, kImpactEnergyResolution);
  }
}

// An empty CSV field for a tier without mesh compliance.
std::string ComplianceErrorCsv(std::optional<double> error) {
  std::ostringstream field;
  field.precision(10);
  if (error) field << *error;
  return field.str();
}

// The rigid-body modes left out of the frequency comparison: one line when every tier has the
// full model's count, else per tier.
void PrintRigidBodyModes(const TiersComparison& c) {
  const int full = c.full_fe_rigid_body_modes;
  bool same = true;
  for (const TierRow& r : c.rows) same = same && r.rigid_body_modes == full;
  std::string text = fmt::format("full FE {}", full);
  if (same) {
    text += ", every tier the same";
  } else {
    for (const TierRow& r : c.rows) text += fmt::format(", {} {}", r.name, r.rigid_body_modes);
  }
  fmt::print("  rigid-body modes (not compared): {}\n", text);
}

// tiers.csv, tiers.json and tiers.png (the tiers that ran) into `out`, committed.
void WriteTiersFolder(OutputFolder& out, const TiersComparison& comparison,
                      const nlohmann::json& doc, const TiersCommandOptions& options) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "tier,method,dof,state_dim,max_frequency_error,static_compliance_error,te_rms_m,"
         "te_rms_difference,rattle_index_j,rattle_index_difference,matvec_per_cycle,"
         "us_per_cycle,real_time_ratio,table_bytes,status\n";
  for (const TierRow& r : comparison.rows) {
    csv << r.name << ',' << SolverMethodName(r.method) << ',' << r.dof << ',' << r.state_dim << ','
        << r.max_frequency_error << ',' << ComplianceErrorCsv(r.compliance_error) << ','
        << CsvNumber(r.te_rms) << ',' << CsvNumber(r.te_rms_difference) << ','
        << CsvNumber(r.rattle_index) << ',' << CsvNumber(r.rattle_index_difference) << ','
        << CsvNumber(r.matvec_per_cycle) << ',' << CsvNumber(r.us_per_cycle) << ','
        << CsvNumber(r.real_time_ratio) << ',' << r.table_bytes << ',' << SolverStatusName(r.status)
        << '\n';
  }
  out.Write("tiers.csv", csv.str());
  out.Write("tiers.json", doc.dump(1) + "\n");
#ifdef GEARNVH_HAVE_RENDER
  std::vector<TierPoint> points;
  for (const TierRow& r : comparison.rows) {
    if (r.ok()) {
      points.push_back({r.name, r.us_per_cycle, r.max_frequency_error, r.te_rms_difference});
    }
  }
  const render::LinePlot plot = TierComparisonFigure("cost (µs per mesh cycle)", points,
                                                     "TE RMS difference to the finest tier");
  const render::RenderStatus status = render::RenderLinePlot(
      plot, {options.width, options.height, options.dpi}, (out.staging() / "tiers.png").string());
  if (!status.ok) throw std::runtime_error("tiers.png: " + status.message);
#else
  (void)options;
#endif
  out.Commit();
}

// The text table: a row per tier, a failed tier with its status and why it stopped.
void PrintTiersTable(const TiersComparison& comparison) {
  const std::vector<TierRow>& rows = comparison.rows;
  fmt::print("  {:<20} {:>4} {:>5} {:>9} {:>10} {:>10} {:>9} {:>10} {:>9} {:>9} {:>9} {:>9}\n",
             "tier", "DOF", "state", "max df/f", "dg/g", "TE RMS µm", "vs finest", "rattle J",
             "vs finest", "matvec/c", "µs/cycle", "x real");
  for (const TierRow& r : rows) {
    fmt::print("  {:<20} {:>4} {:>5} {:>9.2e} {:>10} ", r.name, r.dof, r.state_dim,
               r.max_frequency_error, ComplianceErrorText(r.compliance_error));
    if (!r.ok()) {
      fmt::print("failed ({}): {}\n", SolverStatusName(r.status), r.message);
      continue;
    }
    fmt::print("{:>10.4f} {:>9.2e} {:>10.3e} {:>9.2e} {:>9.1f} {:>9.2f} {:>9.2f}\n", r.te_rms * 1e6,
               r.te_rms_difference, r.rattle_index, r.rattle_index_difference, r.matvec_per_cycle,
               r.us_per_cycle, r.real_time_ratio);
  }
  const TierRow& finest = rows[comparison.finest];
  fmt::print(
      "  finest tier: {}; frequencies of each tier compared with the closest full-FE "
      "frequency\n",
      finest.ok() ? finest.name : "none (every tier's run stopped)");
  PrintRigidBodyModes(comparison);
}

}  // namespace

int TiersExitCode(int failed, size_t tiers) {
  if (failed == 0) return 0;
  fmt::print(stderr, "error: {} of {} tiers failed (listed in the output)\n", failed, tiers);
  return 1;
}

double TierFrequencyError(const ReducedModel& reduced, const ModalSummary& full) {
  double worst = 0.0;
  for (size_t k = 0; k < reduced.natural_frequencies_hz.size() && k < 6; ++k) {
    worst = std::max(worst,
                     ClosestRelativeError(reduced.natural_frequencies_hz[k], full.frequencies_hz));
  }
  return worst;
}

TiersComparison CompareTiers(const GearboxSpec& spec, const SolverOptions& solver,
                             const TiersProgress& progress,
                             const std::function<std::string(RunMemory&)>& before_run_memory) {
  solver.Validate();
  const ComponentModel model = BuildComponentModel(spec);
  // Enough full-FE modes that every tier frequency has its counterpart.
  const ModalSummary full = FullModelFrequencies(model, 60);
  const std::vector<ReducedModel> tiers = ReduceAvailableTiers(model);
  TiersComparison out;
  std::vector<TierRow>& rows = out.rows;
  const size_t total = tiers.size() + 1;
  for (const ReducedModel& r : tiers) {
    ThrowIfCancelled(solver.cancel);
    if (progress) progress(rows.size() + 1, total, r.name);
    rows.push_back(RunTier(spec, model, r, full, solver, r.name, before_run_memory));
    if (r.tier == Tier::kN20Mta) {
      SolverOptions fused = solver;
      ApplyLadderMethod(LadderMethod::kFused, fused);
      rows.push_back(RunTier(spec, model, r, full, fused, r.name + " + fusion", before_run_memory));
    }
  }
  CompareToFinest(out);
  nlohmann::json list = nlohmann::json::array();
  for (const TierRow& r : rows) list.push_back(TierRowJson(r));
  out.full_fe_dof = model.dofs;
  out.full_fe_rigid_body_modes = full.rigid_body_modes;
  out.doc = {
      {"full_fe_dof", model.dofs},
      {"full_fe_rigid_body_modes", full.rigid_body_modes},
      {"full_fe_frequencies_hz", full.frequencies_hz},
      {"finest_tier", rows[out.finest].ok() ? nlohmann::json(rows[out.finest].name) : nullptr},
      {"failed_tiers", out.failed},
      {"cycles", solver.cycles},
      {"transient_cycles", solver.transient_cycles},
      {"tiers", list}};
  return out;
}

int RunTiers(const TiersCommandOptions& options) {
  return RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    if (loaded.schema == 2) return RunTrainTiers(options, loaded.train);
    const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
    const GearboxSpec& spec = *loaded.pair;
    SolverOptions solver;
    ApplyLadderMethod(LadderMethod::kV3, solver);
    solver.cycles = options.cycles.value_or(std::min(spec.analysis.cycles, 400));
    solver.transient_cycles =
        options.transient.value_or(std::min(spec.analysis.transient_cycles, 200));
    RequireRunLengthOfOptions(loaded.train, spec.operating.speed, solver.cycles,
                              solver.transient_cycles, options.cycles, options.transient);
    const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
    TiersProgress progress;
    if (on_terminal) {
      progress = [](size_t done, size_t total, const std::string& name) {
        fmt::print(stderr, "\rtiers: {}/{} ({})        ", done, total, name);
      };
    }
    // Every tier records the same cycles: checked before each run, said once.
    bool memory_said = false;
    const TiersComparison comparison =
        CompareTiers(spec, solver, progress, [&](RunMemory& need) -> std::string {
          const std::string warning =
              options.cycles
                  ? CheckRunMemory(need, AvailableMemory(), "--cycles",
                                   std::to_string(solver.cycles))
                  : CheckRunMemory(need, AvailableMemory(), "analysis.cycles",
                                   std::to_string(solver.cycles),
                                   fmt::format("tiers records {} of them (at most 400); fewer "
                                               "recorded cycles (--cycles) need less",
                                               solver.cycles));
          if (!warning.empty() && !memory_said) fmt::print(stderr, "warning: {}\n", warning);
          memory_said = memory_said || !warning.empty();
          return {};
        });
    if (on_terminal) fmt::print(stderr, "\n");
    nlohmann::json doc = comparison.doc;
    doc["name"] = spec.name;
    doc["file"] = options.file;
    RequireFinite(doc, "tiers");
    if (out) WriteTiersFolder(*out, comparison, doc, options);
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      fmt::print("{}  ({}): modal tiers against the full FE model ({} DOF), {} each\n", spec.name,
                 options.file, comparison.full_fe_dof,
                 Count(solver.cycles, "mesh cycle", "mesh cycles"));
      PrintTiersTable(comparison);
    }
    return TiersExitCode(comparison.failed, comparison.rows.size());
  });
}

}  // namespace gearnvh::app
