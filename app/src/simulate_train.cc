#include "simulate_train.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>

#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/train_atlas.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/train_lyapunov.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "output_folder.h"
#include "result_documents.h"
#include "time_histories.h"
#include "train_command_options.h"
#include "uff_export.h"

namespace gearnvh::app {
namespace {

constexpr int kTraceSamplesPerCycle = 32;

// Each mesh's harmonics, as the pair lists them (MeshHarmonicsText): every line of every source
// down to the rounding floor would be hundreds of lines per mesh; they are in --json.
void PrintTrainSidebands(const TrainOperatingPoint& op) {
  if (op.sideband_window_common_periods > 0) {
    fmt::print(
        "\n  TE mesh harmonics per mesh over {} ({:.4g} s; shaft-order lines and sidebands "
        "in --json):\n",
        Count(op.sideband_window_common_periods, "common period", "common periods"),
        op.tables.common_period * static_cast<double>(op.sideband_window_common_periods));
    for (size_t i = 0; i < op.sidebands.size(); ++i) {
      const std::string text = MeshHarmonicsText(op.sidebands[i].rows);
      fmt::print("    {:<10}{}\n", op.tables.meshes[i].name,
                 text.empty() ? "no harmonic stands out" : text);
    }
  }
  for (const std::string& note : op.sideband_notes) fmt::print("  (spectrum: {})\n", note);
}

// The simulated and recorded time, with the cycles of the first mesh asked for; a stopped run
// says how many it ran instead.
void PrintSimulatedTime(const TrainOperatingPoint& op, long transient, long cycles) {
  const TrainStepperSummary& s = op.summary;
  const TrainMeshTable& first = op.tables.meshes.front();
  if (op.ok()) {
    fmt::print("  simulated           {:.4f} s ({} + {} cycles of {}), {:.4f} s recorded\n",
               s.simulated_time, transient, cycles, first.name, op.stats.recorded_time);
    return;
  }
  fmt::print(
      "  simulated           {:.4f} s ({:.1f} of the {} + {} cycles of {} asked for: stopped), "
      "{:.4f} s ({:.1f} cycles) recorded\n",
      s.simulated_time, s.simulated_time / first.period, transient, cycles, first.name,
      op.stats.recorded_time, op.stats.recorded_time / first.period);
}

const char* JumpsName(TrainStepperSummary::Jumps jumps) {
  using J = TrainStepperSummary::Jumps;
  switch (jumps) {
    case J::kJumped:
      return "jumped";
    case J::kDisabled:
      return "disabled";
    case J::kNoCommonPeriod:
      return "no common period";
    case J::kPeriodTooLong:
      return "common period too long";
    case J::kTransientTooShort:
      return "transient too short";
    case J::kNoConstantContact:
      return "no constant contact";
    case J::kMapRefused:
      return "cycle map refused";
    case J::kNotCertified:
      return "not certified";
  }
  return "";
}

const char* CycleMapName(TrainCycleMap::Info info) {
  using I = TrainCycleMap::Info;
  switch (info) {
    case I::kSuccess:
      return "success";
    case I::kNoOrbit:
      return "no periodic orbit";
    case I::kNotContracting:
      return "not contracting";
    case I::kNoMargin:
      return "orbit touches a wall";
    case I::kDefectiveBasis:
      return "defective eigenbasis";
  }
  return "";
}

nlohmann::json JumpsJson(const TrainTables& tables, const TrainStepperOptions& solver,
                         const TrainStepperSummary& s) {
  return {{"status", JumpsName(s.jumps)},
          {"periods", s.jumped_periods},
          {"time_s", s.jumped_time},
          {"mesh_cycles", s.jumped_time / tables.meshes.front().period},
          {"certificates", s.certificates},
          {"cycle_map",
           {{"builds", s.cycle_map_builds},
            {"info", CycleMapName(s.cycle_map_info)},
            {"segments_per_period", s.cycle_map_segments},
            {"limit_segments", solver.max_cycle_map_segments},
            {"min_jump_periods", solver.min_jump_periods},
            {"bytes", s.cycle_map_bytes}}}};
}

nlohmann::json SegmentRunsJson(const TrainStepperOptions& solver, const TrainStepperSummary& s) {
  return {{"runs", s.fused_runs},
          {"grid_segments", s.fused_grid_segments},
          {"refusals", s.fusion_refusals},
          {"tables", s.fusion_tables},
          {"bytes", s.fusion_bytes},
          {"levels", solver.fusion_levels},
          {"min_periods", solver.fusion_min_periods}};
}

void PrintJumps(const TrainTables& tables, const TrainStepperOptions& solver,
                const TrainStepperSummary& s) {
  using J = TrainStepperSummary::Jumps;
  if (s.jumps == J::kJumped) {
    fmt::print(
        "  certified jumps     {} common periods ({:.0f} cycles of {}, {:.4f} s) of the transient "
        "jumped; cycle map of {} grid segments, {:.1f} KiB\n",
        s.jumped_periods, s.jumped_time / tables.meshes.front().period, tables.meshes.front().name,
        s.jumped_time, s.cycle_map_segments, s.cycle_map_bytes / 1024.0);
  } else if (s.jumps == J::kPeriodTooLong) {
    fmt::print(
        "  certified jumps     none: the common period has more than {} grid segments (no cycle "
        "map built)\n",
        solver.max_cycle_map_segments);
  } else if (s.jumps == J::kTransientTooShort) {
    fmt::print(
        "  certified jumps     none: the transient is shorter than {} common periods ({:.4g} s)\n",
        solver.min_jump_periods + 1, tables.common_period);
  } else if (s.jumps == J::kMapRefused) {
    fmt::print("  certified jumps     none: cycle map refused ({})\n",
               CycleMapName(s.cycle_map_info));
  } else {
    fmt::print("  certified jumps     none: {}\n", JumpsName(s.jumps));
  }
}

// Infinity (no positive exponent: no horizon) as null.

void PrintLyapunov(const TrainLyapunovSummary& l) {
  fmt::print("\n  Lyapunov exponents  ({}; free rotation removed; {} saltations over {:.4f} s)\n",
             TrainLyapunovInfoName(l.info), l.saltations, l.averaged_s);
  for (size_t j = 0; j < l.exponents.size(); ++j) {
    fmt::print("    lambda_{}  {:>12.4g} 1/s  ± {:.2g}   {:>10.4g} per forcing cycle\n", j + 1,
               l.exponents[j], l.standard_errors[j], l.per_forcing_cycle[j]);
  }
  if (std::isfinite(l.predictability_horizon_s)) {
    fmt::print("    predictability horizon {:.4g} s ({:.4g} forcing cycles)\n",
               l.predictability_horizon_s, l.predictability_horizon_cycles);
  } else {
    fmt::print("    no positive exponent: no predictability horizon\n");
  }
}

}  // namespace

TrainLyapunovSummary RunTrainLyapunov(const TrainOperatingPoint& op, const TrainRunOptions& run,
                                      int exponents, const std::function<void(double)>& progress) {
  TrainLyapunovOptions options;
  options.exponents = exponents;
  options.transient_cycles = run.transient;
  options.alignment_cycles = std::min<long>(options.alignment_cycles, run.cycles / 4);
  options.cycles = run.cycles;
  options.stepper.cancel = run.cancel;
  options.progress = progress;
  const auto [z0, states0] = TrainStaticState(op.tables);
  return EstimateTrainLyapunov(op.tables, z0, states0, options);
}

nlohmann::json TrainLyapunovJson(const TrainLyapunovSummary& l) {
  return {{"status", TrainLyapunovInfoName(l.info)},
          {"exponents_per_s", l.exponents},
          {"per_forcing_cycle", l.per_forcing_cycle},
          {"per_mesh_cycle", l.per_mesh_cycle},
          {"standard_errors_per_s", l.standard_errors},
          {"forcing_period_s", l.forcing_period},
          {"averaged_s", l.averaged_s},
          {"saltations", l.saltations},
          {"predictability_horizon_s", FiniteOrNull(l.predictability_horizon_s)},
          {"predictability_horizon_cycles", FiniteOrNull(l.predictability_horizon_cycles)}};
}

namespace {

// Each bearing's force on the housing: mean and RMS per direction, and its largest mesh line.
void PrintBearingForces(const TrainOperatingPoint& op, const TrainSpec& spec) {
  if (op.bearing_forces.empty()) return;
  std::vector<std::string> names;
  size_t width = 7;
  for (const TrainBearingForce& f : op.bearing_forces) {
    names.push_back(
        BearingName(spec.shafts[static_cast<size_t>(f.bearing.shaft)].name, f.bearing.index));
    width = std::max(width, names.back().size() + 2);
  }
  const bool lines = !op.bearing_forces.front().lines.empty();
  fmt::print("\n  bearing forces on the housing, N (mean and RMS exact over the record; {})\n",
             lines ? "mesh lines over the sideband window" : "no spectrum window: no mesh lines");
  fmt::print("  {:<{}}{:>24}{:>24}{:>24}  largest mesh line\n", "bearing", width, "x mean / RMS",
             "y mean / RMS", "z mean / RMS");
  constexpr std::array<char, 3> kAxis{'x', 'y', 'z'};
  for (size_t b = 0; b < op.bearing_forces.size(); ++b) {
    const TrainBearingForce& f = op.bearing_forces[b];
    std::string cells;
    for (size_t d = 0; d < 3; ++d) {
      cells += fmt::format("{:>24}", fmt::format("{:.4g} / {:.4g}", f.mean[d], f.rms[d]));
    }
    const TrainBearingForce::Line* largest = nullptr;
    size_t axis = 0;
    for (const TrainBearingForce::Line& l : f.lines) {
      for (size_t d = 0; d < 3; ++d) {
        if (largest == nullptr || l.amplitude[d] > largest->amplitude[axis]) {
          largest = &l;
          axis = d;
        }
      }
    }
    fmt::print("  {:<{}}{}  {}\n", names[b], width, cells,
               largest == nullptr ? std::string("-")
                                  : fmt::format("{} {}: {:.4g}", largest->label, kAxis[axis],
                                                largest->amplitude[axis]));
  }
}

// Each coupling's twist and torque over the record (exact), in degrees and N m.
void PrintCouplings(const TrainOperatingPoint& op) {
  if (op.couplings.empty()) return;
  constexpr double kDeg = 180.0 / std::numbers::pi;
  fmt::print("\n  {:<16}{:>13}{:>12}{:>12}{:>12}{:>15}{:>13}{:>13}\n", "coupling", "twist mean°",
             "RMS°", "min°", "max°", "torque mean", "min N m", "max N m");
  for (const TrainCouplingResponse& c : op.couplings) {
    fmt::print("  {:<16}{:>13.4g}{:>12.4g}{:>12.4g}{:>12.4g}{:>15.4g}{:>13.4g}{:>13.4g}\n", c.name,
               c.twist.mean * kDeg, c.twist.rms * kDeg, c.twist.min * kDeg, c.twist.max * kDeg,
               c.torque.mean, c.torque.min, c.torque.max);
  }
  for (const TrainCouplingResponse& c : op.couplings) {
    for (const TrainCouplingStageStatistics& s : c.stages) {
      fmt::print(
          "    {:<28} entered {} times ({} past +, {} past -; {:.4g} /s), engaged {:.4g} % of the "
          "time\n",
          s.name, s.entries, s.positive_entries, s.negative_entries,
          op.stats.recorded_time > 0.0 ? static_cast<double>(s.entries) / op.stats.recorded_time
                                       : 0.0,
          100.0 * s.engaged_fraction);
    }
  }
}

}  // namespace

nlohmann::json TrainSimulationJson(const TrainOperatingPoint& op, const TrainSpec& spec,
                                   const std::string& file, Tier tier) {
  nlohmann::json doc;
  const TrainTables& tables = op.tables;
  const TrainStepperOptions& solver = op.solver;
  const TrainStepperSummary& s = op.summary;
  const TrainStatistics& stats = op.stats;
  const double wall = op.wall_s;
  doc["schema"] = "gearnvh/2";
  doc["name"] = spec.name;
  doc["file"] = file;
  doc["tier"] = TierName(tier);
  doc["state_dim"] = tables.m;
  doc["method"] = EventMethodName(solver.events);
  doc["input_speed"] = {{"rad_s", spec.operating.speed}, {"rpm", Rpm(spec.operating.speed)}};
  doc["common_period_s"] = tables.common_period;
  doc["warnings"] = op.warnings;
  if (op.adequacy_options) {
    doc["tier_adequacy"] = TierAdequacyJson(op.adequacy, *op.adequacy_options, MeshNames(spec));
  }
  doc["memory_estimate"] = MemoryJson(op.memory);
  doc["summary"] = {{"status", TrainStepperInfoName(s.info)},
                    {"message", TrainStepperMessage(s)},
                    {"simulated_s", s.simulated_time},
                    {"recorded_s", stats.recorded_time},
                    {"wall_s", wall},
                    {"real_time_ratio", wall > 0.0 ? s.simulated_time / wall : 0.0},
                    {"grid_segments", s.grid_segments},
                    {"events", s.events},
                    {"simultaneous_events", s.simultaneous_events},
                    {"grazing", s.grazing},
                    {"start_switches", s.start_switches},
                    {"dense_pieces", s.dense_pieces},
                    {"dyadic_substeps", s.dyadic_substeps},
                    {"dyadic_matvecs", s.dyadic_matvecs},
                    {"jumps", JumpsJson(tables, solver, s)},
                    {"segment_runs", SegmentRunsJson(solver, s)},
                    {"samples", stats.samples},
                    {"cache",
                     {{"bytes", s.cache.bytes},
                      {"peak_bytes", s.cache.peak_bytes},
                      {"limit_bytes", solver.tables.cache_limit_bytes},
                      {"tuples", s.cache.tuples},
                      {"hits", s.cache.hits},
                      {"misses", s.cache.misses},
                      {"evictions", s.cache.evictions},
                      {"decompositions", s.cache.decompositions},
                      {"ill_conditioned", s.cache.ill_conditioned}}}};
  doc["meshes"] = TrainMeshesJson(op);
  doc["sideband_window_common_periods"] = op.sideband_window_common_periods;
  doc["sidebands_notes"] = op.sideband_notes;
  doc["loose_gears"] = TrainLooseGearsJson(op.stats.loose_gears);
  doc["bearings"] = TrainBearingForcesJson(op, spec);
  doc["couplings"] = TrainCouplingsJson(op.couplings, op.stats.recorded_time);
  if (op.histories.dt > 0.0) {
    const TrainHistories& h = op.histories;
    doc["time_histories"] = {{"samples", h.te.empty() ? 0 : h.te.front().size()},
                             {"sample_interval_s", h.dt},
                             {"truncated", h.truncated},
                             {"events", h.events.size()},
                             {"events_truncated", h.events_truncated}};
  }
  return doc;
}

TrainSimulatePlan PlanTrainSimulate(const SimulateOptions& options, const TrainSpec& spec,
                                    const OptionNames& names) {
  const TrainCommandSettings settings =
      CheckTrainCommandOptions(options.tier, spec, options.method, names);
  TrainSimulatePlan plan;
  TrainRunOptions& run = plan.run;
  run.cycles = options.cycles.value_or(spec.analysis.cycles);
  run.transient = options.transient.value_or(spec.analysis.transient_cycles);
  run.samples_per_cycle = kTraceSamplesPerCycle;
  run.events = settings.events;
  run.tier = settings.tier;
  run.allow_slow = options.allow_slow;
  run.names = names;
  run.histories = options.out.has_value() || options.uff.has_value();
  run.bearing_forces = true;
  run.tier_adequacy = true;
  RequireCycleCounts(run.cycles, 1, run.transient, names);
  RequireRunLengthOfOptions(spec, spec.operating.speed, run.cycles, run.transient, options.cycles,
                            options.transient, names);
  plan.lyapunov = options.lyapunov;
  if (!plan.lyapunov) return plan;
  const TrainLyapunovOptions lyapunov_defaults;
  if (run.cycles < lyapunov_defaults.blocks) {
    throw InputError(names("cycles"), 0, std::to_string(run.cycles),
                     "must be >= " + std::to_string(lyapunov_defaults.blocks) + " with " +
                         names("lyapunov") + " (one block per standard-error block)");
  }
  // Tier 1: one body per shaft and per loose gear; a fixed shaft's body stands (speed 0).
  const TrainTopology topology = AnalyseTrainTopology(spec);
  const int bodies = static_cast<int>(topology.bodies.size());
  const int standing =
      static_cast<int>(std::count_if(topology.bodies.begin(), topology.bodies.end(),
                                     [](const TrainBody& b) { return b.speed == 0.0; }));
  const int most = 2 * (bodies - standing) - 2;
  if (*plan.lyapunov < 1 || *plan.lyapunov > most) {
    throw InputError(
        names("lyapunov"), 0, std::to_string(*plan.lyapunov),
        "must be in 1 .. 2n - 2" + std::string(standing > 0 ? " - 2s" : "") + " = " +
            std::to_string(most) + " for this train (" + std::to_string(bodies) + " bodies" +
            (standing > 0 ? ", s = " + std::to_string(standing) + " fixed shafts" : "") +
            "; removed: the free rotation's angle and speed" +
            (standing > 0 ? " and each fixed shaft's two" : "") + ")");
  }
  return plan;
}

int SimulateTrain(const SimulateOptions& options, const TrainSpec& spec) {
  TrainSimulatePlan plan = PlanTrainSimulate(options, spec);
  TrainRunOptions& run = plan.run;
  const Tier tier = run.tier;
  const long cycles = run.cycles, transient = run.transient;
  const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
  // Said on stderr before the run; the text's warning lines at the end leave them out (the JSON
  // keeps every warning), as for a pair.
  std::vector<std::string> said_before_run;
  run.before_run_warning = [&](const std::string& w) {
    fmt::print(stderr, "warning: {}\n", w);
    said_before_run.push_back(w);
  };
  run.before_run_memory = [&](RunMemory& need) {
    if (options.uff) {
      // Per mesh its TE and force; per bearing force row and per coupling (twist and torque) its
      // series (and text) alike, at most.
      MemoryPart uff = OperatingPointUffMemory(need.recorded_samples);
      uff.bytes *= spec.meshes.size() + need.bearing_rows + spec.couplings.size();
      need.parts.push_back(uff);
    }
    return CheckRunMemory(need, AvailableMemory(), options.cycles ? "--cycles" : "analysis.cycles",
                          std::to_string(cycles));
  };
  const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
  const TrainOperatingPoint op = RunTrainOperatingPoint(spec, run, [&](double time, double end) {
    if (!on_terminal) return;
    fmt::print(stderr, "\rsimulate: {:3.0f}% ({:.0f}/{} mesh cycles of {})", 100.0 * time / end,
               static_cast<double>(transient + cycles) * time / end, transient + cycles,
               spec.meshes.front().Name());
  });
  if (on_terminal) fmt::print(stderr, "\n");
  const TrainTables& tables = op.tables;
  const TrainStepperOptions& solver = op.solver;
  const TrainStepperSummary& s = op.summary;
  const TrainStatistics& stats = op.stats;
  const std::vector<std::string>& warnings = op.warnings;
  const double wall = op.wall_s;
  std::optional<TrainLyapunovSummary> lyapunov;
  if (plan.lyapunov && op.ok()) {
    std::function<void(double)> progress;
    if (on_terminal) {
      progress = [](double fraction) {
        fmt::print(stderr, "\rlyapunov: {:3.0f}%", 100.0 * fraction);
      };
    }
    lyapunov = RunTrainLyapunov(op, run, *plan.lyapunov, progress);
    if (on_terminal) fmt::print(stderr, "\n");
  }
  nlohmann::json doc = TrainSimulationJson(op, spec, options.file, tier);
  if (lyapunov) doc["lyapunov"] = TrainLyapunovJson(*lyapunov);
  RequireFinite(doc, "simulate");
  if (out) {
    out->Write("trajectory.csv", [&op, &spec](std::FILE* f) {
      WriteTrainTrajectoryCsv(op.histories, op.tables, spec, f);
    });
    out->Write("events.csv", TrainEventsCsv(op.histories, op.tables));
    out->Write("results.json", doc.dump(2) + "\n");
    out->Commit();
  }
  if (options.uff) WriteUffFile(*options.uff, TrainOperatingPointUff(spec, op));
  if (options.json) {
    std::cout << doc.dump(2) << "\n";
  } else {
    fmt::print("{}  ({}), gear train, {}: {} bodies, {} DOF, {} meshes, state dimension {}\n",
               spec.name, options.file, TierName(tier), tables.bodies(), tables.n,
               tables.gear_meshes, tables.m);
    fmt::print("  operating point     input shaft {} at {}, loads {}\n", spec.operating.input_shaft,
               Format(spec.operating.speed, spec.operating.speed_unit), TrainLoadsText(spec));
    const std::string why = TrainStepperMessage(s);
    fmt::print("  status              {}{}\n", TrainStepperInfoName(s.info),
               why.empty() ? "" : ": " + why);
    if (!op.ok()) fmt::print("                      {}\n", kStoppedRunNote);
    PrintSimulatedTime(op, transient, cycles);
    fmt::print("  contact events      {} ({} simultaneous, {} grazing)\n", s.events,
               s.simultaneous_events, s.grazing);
    fmt::print("  wall time           {:.4f} s: {:.2f}x real time\n", wall,
               wall > 0.0 ? s.simulated_time / wall : 0.0);
    fmt::print(
        "  table cache         {:.1f} MiB held (peak {:.1f} MiB), {} tuples, {} built, {} "
        "decomposed ({} ill-conditioned), {} evicted\n",
        s.cache.bytes / 1048576.0, s.cache.peak_bytes / 1048576.0, s.cache.tuples, s.cache.misses,
        s.cache.decompositions, s.cache.ill_conditioned, s.cache.evictions);
    PrintJumps(tables, solver, s);
    if (s.fused_runs > 0) {
      fmt::print(
          "  segment runs        {} grid segments of the transient in {} certified runs ({:.1f} "
          "MiB of run tables)\n",
          s.fused_grid_segments, s.fused_runs, s.fusion_bytes / 1048576.0);
    }
    fmt::print("\n  {:<10}{:>12}{:>12}{:>12}{:>14}{:>9}{:>9}{:>11}\n", "mesh", "TE mean µm",
               "TE RMS µm", "TE p-p µm", "force max N", "drive", "back", "separated");
    for (const TrainMeshStatistics& m : stats.meshes) {
      fmt::print("  {:<10}{:>12.4f}{:>12.4f}{:>12.4f}{:>14.2f}{:>9}{:>9}{:>10.1f}%\n", m.name,
                 m.te_mean * 1e6, m.te_rms * 1e6, m.te_peak_to_peak * 1e6, m.force_max,
                 m.drive_impacts, m.back_impacts, 100.0 * m.free_time_fraction);
    }
    if (!stats.loose_gears.empty()) {
      fmt::print("\n  loose gears by impact energy (a gear without impacts does not rattle):\n");
      fmt::print("    {:<6}{:<10}{:>13}{:>11}{:>11}{:>13}{:>13}{:>15}\n", "rank", "gear",
                 "energy mW", "drive /s", "back /s", "v RMS mm/s", "v max mm/s", "accel rad/s²");
      for (const TrainLooseGearStatistics& g : stats.loose_gears) {
        fmt::print("    {:<6}{:<10}{:>13.4g}{:>11.1f}{:>11.1f}{:>13.4g}{:>13.4g}{:>15.1f}\n",
                   g.rank > 0 ? std::to_string(g.rank) : "-", g.name,
                   g.impact_energy_per_second * 1e3, g.drive_impacts_per_second,
                   g.back_impacts_per_second, g.impact_velocity_rms * 1e3,
                   g.impact_velocity_max * 1e3, g.rattle_index);
      }
    }
    fmt::print(
        "  (TE is measured from the nominal rigid rotation, so its mean includes the mesh's half "
        "backlash b:\n   drive contact closes the gap at TE = b; b per mesh in µm:");
    for (size_t i = 0; i < stats.meshes.size(); ++i)
      fmt::print(" {} {:.4g}", stats.meshes[i].name, tables.meshes[i].half_backlash * 1e6);
    fmt::print(")\n");
    PrintTrainSidebands(op);
    PrintBearingForces(op, spec);
    PrintCouplings(op);
    fmt::print(
        "  (TE, force, rattle index and couplings exact: closed-form integrals and extrema of the "
        "recorded trajectory;\n   impacts and separation from the exact events)\n");
    if (lyapunov) PrintLyapunov(*lyapunov);
    for (const std::string& w : warnings) {
      if (std::ranges::find(said_before_run, w) == said_before_run.end()) {
        fmt::print("  warning: {}\n", w);
      }
    }
  }
  const bool lyapunov_ok = !lyapunov || lyapunov->info == TrainLyapunovSummary::Info::kSuccess;
  return s.info == TrainStepperSummary::Info::kSuccess && lyapunov_ok ? 0 : 1;
}

}  // namespace gearnvh::app
