#include "train_tiers.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "finite_results.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/train_structure.h"
#include "gearnvh/reduction/train_reduction.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "output_folder.h"
#include "train_command_options.h"

namespace gearnvh::app {
namespace {

TrainTierRow RunTier(const TrainSpec& spec, const GearTrain& train, TrainTables tables,
                     TrainRunOptions run) {
  run.tier = tables.tier;
  const Tier tier = tables.tier;
  // Every tier steps the same cycles: whether a transient is certified and jumped depends on the
  // tier, and the cost columns compare stepping.
  run.jumps = false;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, train, std::move(tables), run);
  TrainTierRow row;
  row.name = TierName(tier);
  row.dof = op.tables.n;
  row.state_dim = op.tables.m;
  row.table_bytes = op.summary.cache.peak_bytes;
  if (!op.ok()) {
    row.info = op.summary.info;
    row.message = TrainStepperMessage(op.summary);
    row.te_rms.assign(op.stats.meshes.size(), kNoResult);
    for (bool loose : op.tables.loose) {
      if (loose) row.rattle_index.push_back(kNoResult);
    }
    row.us_per_cycle = row.real_time_ratio = kNoResult;
    return row;
  }
  for (const TrainMeshStatistics& m : op.stats.meshes) row.te_rms.push_back(m.te_rms);
  // Loose gears in body order (the statistics are ranked).
  for (int b = 0; b < op.tables.bodies(); ++b) {
    if (!op.tables.loose[static_cast<size_t>(b)]) continue;
    for (const TrainLooseGearStatistics& g : op.stats.loose_gears) {
      if (g.name == op.tables.body_names[static_cast<size_t>(b)])
        row.rattle_index.push_back(g.rattle_index);
    }
  }
  const long cycles = run.transient + run.cycles;
  row.us_per_cycle = 1e6 * op.wall_s / static_cast<double>(std::max(1L, cycles));
  row.real_time_ratio = op.wall_s > 0.0 ? op.summary.simulated_time / op.wall_s : 0.0;
  return row;
}

// The differences of every row to the finest (succeeded, most DOF); NaN for a failed row.
void CompareToFinest(TrainTiersComparison& out) {
  std::vector<TrainTierRow>& rows = out.rows;
  out.finest = FinestRow(rows);
  const TrainTierRow& finest = rows[out.finest];
  const bool compared = finest.ok();
  for (TrainTierRow& r : rows) {
    out.failed += r.ok() ? 0 : 1;
    for (size_t i = 0; i < r.te_rms.size(); ++i) {
      r.te_rms_difference.push_back(
          compared ? RelativeDifference(r.te_rms[i], finest.te_rms[i], kTeResolution) : kNoResult);
    }
    for (size_t i = 0; i < r.rattle_index.size(); ++i) {
      r.rattle_index_difference.push_back(
          compared ? RelativeDifference(r.rattle_index[i], finest.rattle_index[i],
                                        kAngularAccelerationResolution)
                   : kNoResult);
    }
  }
}

nlohmann::json TrainTierRowJson(const TrainTierRow& r, const TrainTiersComparison& c) {
  nlohmann::json meshes = nlohmann::json::array(), loose = nlohmann::json::array();
  for (size_t i = 0; i < r.te_rms.size(); ++i) {
    meshes.push_back({{"name", c.meshes[i]},
                      {"te_rms_m", ResultOrNull(r.ok(), r.te_rms[i])},
                      {"te_rms_difference_to_finest", FiniteOrNull(r.te_rms_difference[i])}});
  }
  for (size_t i = 0; i < r.rattle_index.size(); ++i) {
    loose.push_back(
        {{"name", c.loose_gears[i]},
         {"rattle_index", ResultOrNull(r.ok(), r.rattle_index[i])},
         {"rattle_index_difference_to_finest", FiniteOrNull(r.rattle_index_difference[i])}});
  }
  return {{"name", r.name},
          {"status", TrainStepperInfoName(r.info)},
          {"message", r.message},
          {"dof", r.dof},
          {"state_dim", r.state_dim},
          {"meshes", meshes},
          {"loose_gears", loose},
          {"us_per_cycle", ResultOrNull(r.ok(), r.us_per_cycle)},
          {"real_time_ratio", ResultOrNull(r.ok(), r.real_time_ratio)},
          {"table_bytes", r.table_bytes}};
}

}  // namespace

TrainTiersComparison CompareTrainTiers(const TrainSpec& spec, TrainRunOptions run,
                                       const TiersProgress& progress) {
  run.Validate();
  run.spectra = false;
  const GearTrain train = BuildGearTrain(spec);
  const TrainStructure structure = AssembleTrainStructure(spec, train);
  std::vector<Tier> tiers;
  for (Tier t : {Tier::kTier1, Tier::kTier2, Tier::kTier3, Tier::kTier4, Tier::kTier5,
                 Tier::kN20Simple, Tier::kN20Mta}) {
    if (t == Tier::kTier1 || TrainTierAvailable(structure, t)) tiers.push_back(t);
  }
  TrainTiersComparison out;
  for (const TrainMeshModel& m : train.meshes) out.meshes.push_back(m.name);
  for (const TrainBody& b : train.topology.bodies) {
    if (b.kind == BodyKind::kLooseGear) out.loose_gears.push_back(b.name);
  }
  // Every tier's tables and cost before any runs; the runs then use those tables.
  std::vector<TrainTables> tables;
  std::vector<RunCostEstimate> costs;
  TrainTableOptions table_options;
  table_options.cancel = run.cancel;
  for (Tier t : tiers) {
    tables.push_back(BuildTrainTablesAtTier(spec, train, t, table_options));
    const double period = tables.back().meshes.front().period;
    costs.push_back(EstimateRunCost(
        tables.back(), static_cast<double>(run.cycles + run.transient) * period, &spec));
  }
  const std::string slow = CheckRunCost(CombineRunCosts(costs, 1), run.allow_slow,
                                        fmt::format("the {} tiers' runs", costs.size()), run.names);
  if (!slow.empty() && run.before_run_warning) run.before_run_warning(slow);
  run.allow_slow = true;
  run.before_run_warning = {};
  for (TrainTables& t : tables) {
    ThrowIfCancelled(run.cancel);
    if (progress) progress(out.rows.size() + 1, tiers.size(), TierName(t.tier));
    out.rows.push_back(RunTier(spec, train, std::move(t), run));
  }
  CompareToFinest(out);
  nlohmann::json list = nlohmann::json::array();
  for (const TrainTierRow& r : out.rows) list.push_back(TrainTierRowJson(r, out));
  const TrainTierRow& finest = out.rows[out.finest];
  out.doc = {{"schema", "gearnvh/2"},
             {"finest_tier", finest.ok() ? nlohmann::json(finest.name) : nullptr},
             {"failed_tiers", out.failed},
             {"cycles", run.cycles},
             {"transient_cycles", run.transient},
             {"tiers", list}};
  return out;
}

TrainRunOptions PlanTrainTiers(const TiersCommandOptions& options, const TrainSpec& spec,
                               const OptionNames& names) {
  TrainRunOptions run;
  run.cycles = options.cycles.value_or(std::min(spec.analysis.cycles, 400));
  run.transient = options.transient.value_or(std::min(spec.analysis.transient_cycles, 200));
  run.allow_slow = options.allow_slow;
  run.names = names;
  RequireCycleCounts(run.cycles, 1, run.transient, names);
  RequireRunLengthOfOptions(spec, spec.operating.speed, run.cycles, run.transient, options.cycles,
                            options.transient, names);
  return run;
}

nlohmann::json TrainTiersDocument(const TrainTiersComparison& c, const TrainSpec& spec,
                                  const std::string& file) {
  nlohmann::json doc = c.doc;
  doc["name"] = spec.name;
  doc["file"] = file;
  return doc;
}

namespace {

// tiers.csv: one row per tier and mesh or loose gear (long format: any number of each).
std::string TrainTiersCsv(const TrainTiersComparison& c) {
  std::ostringstream csv;
  csv.precision(10);
  csv << "tier,dof,state_dim,item,name,value,difference_to_finest,us_per_cycle,real_time_ratio,"
         "table_bytes,status\n";
  for (const TrainTierRow& r : c.rows) {
    const auto line = [&](const char* item, const std::string& name, double value,
                          double difference) {
      csv << r.name << ',' << r.dof << ',' << r.state_dim << ',' << item << ',' << name << ','
          << CsvNumber(value) << ',' << CsvNumber(difference) << ',' << CsvNumber(r.us_per_cycle)
          << ',' << CsvNumber(r.real_time_ratio) << ',' << r.table_bytes << ','
          << TrainStepperInfoName(r.info) << '\n';
    };
    for (size_t i = 0; i < r.te_rms.size(); ++i)
      line("te_rms_m", c.meshes[i], r.te_rms[i], r.te_rms_difference[i]);
    for (size_t i = 0; i < r.rattle_index.size(); ++i) {
      line("rattle_index", c.loose_gears[i], r.rattle_index[i], r.rattle_index_difference[i]);
    }
  }
  return csv.str();
}

// A table of one value per tier and item (mesh or loose gear); a failed tier says so once.
void PrintTrainTierValues(const TrainTiersComparison& c, const std::vector<std::string>& items,
                          std::vector<double> TrainTierRow::*values,
                          std::vector<double> TrainTierRow::*differences, double scale,
                          const char* format) {
  fmt::print("  {:<12}", "tier");
  for (const std::string& m : items) fmt::print(" {:>22}", m);
  fmt::print("\n");
  for (const TrainTierRow& r : c.rows) {
    fmt::print("  {:<12}", r.name);
    if (!r.ok()) fmt::print(" failed");
    for (size_t i = 0; r.ok() && i < (r.*values).size(); ++i) {
      fmt::print(" {:>11} ({:>8.1e})", fmt::format(fmt::runtime(format), scale * (r.*values)[i]),
                 (r.*differences)[i]);
    }
    fmt::print("\n");
  }
}

void PrintTrainTiers(const TrainTiersComparison& c, const TrainSpec& spec,
                     const TrainRunOptions& run, const std::string& file) {
  fmt::print("{}  ({}): the train's tiers side by side, {} + {} cycles of {} each\n", spec.name,
             file, run.transient, run.cycles, c.meshes.front());
  fmt::print("  {:<12} {:>5} {:>6} {:>10} {:>10} {:>12}\n", "tier", "DOF", "state", "µs/cycle",
             "x real", "cache MiB");
  for (const TrainTierRow& r : c.rows) {
    fmt::print("  {:<12} {:>5} {:>6} ", r.name, r.dof, r.state_dim);
    if (!r.ok()) {
      fmt::print("failed ({}): {}\n", TrainStepperInfoName(r.info), r.message);
      continue;
    }
    fmt::print("{:>10.1f} {:>10.3f} {:>12.2f}\n", r.us_per_cycle, r.real_time_ratio,
               static_cast<double>(r.table_bytes) / (1 << 20));
  }
  const TrainTierRow& finest = c.rows[c.finest];
  const std::string reference = finest.ok() ? finest.name : "none: every tier's run stopped";
  fmt::print("\n  TE RMS µm (relative difference to {})\n", reference);
  PrintTrainTierValues(c, c.meshes, &TrainTierRow::te_rms, &TrainTierRow::te_rms_difference, 1e6,
                       "{:.4f}");
  if (!c.loose_gears.empty()) {
    fmt::print("\n  rattle index rad/s² (relative difference to {})\n", reference);
    PrintTrainTierValues(c, c.loose_gears, &TrainTierRow::rattle_index,
                         &TrainTierRow::rattle_index_difference, 1.0, "{:.4g}");
  }
}

}  // namespace

int RunTrainTiers(const TiersCommandOptions& options, const TrainSpec& spec) {
  TrainRunOptions run = PlanTrainTiers(options, spec);
  run.before_run_warning = [](const std::string& w) { fmt::print(stderr, "warning: {}\n", w); };
  const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
  const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
  TiersProgress progress;
  if (on_terminal) {
    progress = [](size_t done, size_t total, const std::string& name) {
      fmt::print(stderr, "\rtiers: {}/{} ({})        ", done, total, name);
    };
  }
  const TrainTiersComparison c = CompareTrainTiers(spec, run, progress);
  if (on_terminal) fmt::print(stderr, "\n");
  const nlohmann::json doc = TrainTiersDocument(c, spec, options.file);
  RequireFinite(doc, "tiers");
  if (out) {
    out->Write("tiers.csv", TrainTiersCsv(c));
    out->Write("tiers.json", doc.dump(1) + "\n");
    out->Commit();
  }
  if (options.json) {
    std::cout << doc.dump(1) << "\n";
  } else {
    PrintTrainTiers(c, spec, run, options.file);
  }
  return TiersExitCode(c.failed, c.rows.size());
}

}  // namespace gearnvh::app
