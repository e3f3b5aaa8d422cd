#include "simulate_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <numeric>
#include <sstream>

#include "atomic_file.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/rattle.h"
#include "gearnvh/nvh/spectrum.h"
#include "gearnvh/nvh/transmission_error.h"
#include "gearnvh/reduction/reduced_model.h"
#include "output_folder.h"
#include "result_documents.h"
#include "simulate_train.h"
#include "time_histories.h"
#include "train_command_options.h"
#include "uff_export.h"

namespace gearnvh::app {

Tier ParseTier(const std::string& text, const std::string& field) {
  if (text == "1") return Tier::kTier1;
  if (text == "2") return Tier::kTier2;
  if (text == "3") return Tier::kTier3;
  if (text == "4") return Tier::kTier4;
  if (text == "5" || text == "N40 full") return Tier::kTier5;
  if (text == "N20 simple") return Tier::kN20Simple;
  if (text == "N20 MTA") return Tier::kN20Mta;
  throw InputError(field, 0, text, "must be 1..5, \"N40 full\", \"N20 simple\" or \"N20 MTA\"");
}

void RequirePairTier(const ComponentModel& model, Tier tier,
                     const std::optional<std::string>& tier_option) {
  try {
    RequireTierAvailable(model, tier);
  } catch (const TierNotAvailable& e) {
    throw UserNamed(e, PairTierNames(tier_option));
  }
}

LadderMethod ParseMethod(const std::string& text, const std::string& field) {
  std::string choices;
  for (const LadderMethod m : kLadderMethods) {
    if (text == LadderMethodName(m)) return m;
    choices += std::string(choices.empty() ? "" : ", ") + LadderMethodName(m);
  }
  throw InputError(field, 0, text, "must be one of " + choices);
}

int RunSimulate(const SimulateOptions& options) {
  return RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    if (loaded.schema == 2) return SimulateTrain(options, loaded.train);
    if (options.lyapunov) {
      throw InputError("--lyapunov", 0, std::to_string(*options.lyapunov),
                       "is available on gear trains (schema gearnvh/2); a single pair's exponent "
                       "is in `gearnvh atlas`");
    }
    const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);
    const GearboxSpec spec = std::move(*loaded.pair);
    const Tier tier = options.tier ? ParseTier(*options.tier) : spec.analysis.tier;
    SolverOptions solver;
    solver.cycles = options.cycles.value_or(spec.analysis.cycles);
    solver.transient_cycles = options.transient.value_or(spec.analysis.transient_cycles);
    ApplyLadderMethod(options.method, solver);
    solver.Validate();
    RequireRunLengthOfOptions(loaded.train, spec.operating.speed, solver.cycles,
                              solver.transient_cycles, options.cycles, options.transient);
    const ComponentModel model = BuildComponentModel(spec);
    RequirePairTier(model, tier, options.tier);
    // Progress on a terminal only; quiet when stderr is piped.
    const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
    ProgressCallback progress;
    if (on_terminal) {
      progress = [](long done, long total) {
        fmt::print(stderr, "\rsimulate: {:3d}% ({}/{} mesh cycles)", 100 * done / total, done,
                   total);
      };
    }
    // Warnings about the run's cost before it starts, as for a train (simulate_train.cc); the
    // text's warning lines at the end leave them out (the JSON keeps every warning).
    std::vector<std::string> said_before_run;
    const OperatingPointAnalysis op = AnalyseOperatingPoint(
        spec, model, tier, solver, progress,
        [&](const std::string& w) {
          fmt::print(stderr, "warning: {}\n", w);
          said_before_run.push_back(w);
        },
        [&](RunMemory& need) {
          if (options.uff) need.parts.push_back(OperatingPointUffMemory(need.recorded_samples));
          return CheckRunMemory(need, AvailableMemory(),
                                options.cycles ? "--cycles" : "analysis.cycles",
                                std::to_string(solver.cycles));
        });
    if (on_terminal) fmt::print(stderr, "\n");
    const SolverSummary& summary = op.result.summary;
    const Trajectory& trajectory = op.result.trajectory;
    const RattleIndices& rattle = op.rattle;
    const TransmissionErrorStats& te = op.te;
    const std::vector<SidebandRow>& sideband_rows = op.sidebands;
    const long window = op.sideband_window;
    nlohmann::json doc = OperatingPointJson(op);
    doc["name"] = spec.name;
    doc["file"] = options.file;
    RequireFinite(doc, "simulate");
    if (out) {
      out->Write("trajectory.csv",
                 [&trajectory](std::FILE* f) { WriteTrajectoryCsv(trajectory, f); });
      out->Write("events.csv", EventsCsv(trajectory));
      out->Write("results.json", doc.dump(2) + "\n");
      out->Commit();
    }
    if (options.uff) WriteUffFile(*options.uff, OperatingPointUff(spec, op));
    if (options.json) {
      std::cout << doc.dump(2) << "\n";
    } else {
      const SolverSummary& s = summary;
      fmt::print("{}  ({}), {}: state dimension {}\n", spec.name, options.file, op.tier_name,
                 op.tables.m);
      fmt::print("  operating point     pinion at {}, {}\n",
                 Format(spec.operating.speed, spec.operating.speed_unit), TorqueText(spec));
      fmt::print("  status              {}\n", SolverStatusName(s.status));
      if (s.status != SolverStatus::kSuccess) {
        fmt::print("  stopped             {}\n                      {}\n", s.message,
                   kStoppedRunNote);
      }
      fmt::print("  mesh cycles         {} ({} recorded)\n", s.mesh_cycles, s.recorded_cycles);
      fmt::print(
          "  contact events      {} ({:.3f} per cycle): {} drive impacts, {} back impacts, {} "
          "separations, {} grazing\n",
          s.events, s.events_per_cycle, s.drive_impacts, s.back_impacts, s.separations, s.grazing);
      fmt::print("  matvec per cycle    {:.1f} ({}: {} fused, {} jumped{})\n", s.matvec_per_cycle,
                 SolverMethodName(solver.method), Count(s.fused_cycles, "cycle", "cycles"),
                 s.jumped_cycles, s.contact_certified ? ", permanent contact certified" : "");
      fmt::print("  wall time           {:.4f} s for {:.4f} s simulated: {:.2f}x real time\n",
                 s.wall_s, s.simulated_s, s.real_time_ratio);
      fmt::print("  tables              {:.1f} KiB\n", s.table_bytes / 1024.0);
      if (solver.events == EventMethod::kSpectral) {
        fmt::print(
            "  v3 decompositions   max cond(S) {:.3g}, {} (segment, state) fell back to v2\n",
            s.spectral_max_condition, s.spectral_fallback_systems);
      }
      fmt::print("  TE                  mean {:.4f} µm, RMS {:.4f} µm, p-p {:.4f} µm\n",
                 te.mean * 1e6, te.rms * 1e6, te.peak_to_peak * 1e6);
      fmt::print("                      ({})\n", TeMeanNote(te, model.half_backlash));
      fmt::print("  mesh force          mean {:.2f} N, max {:.2f} N, dynamic factor {:.3f}\n",
                 te.mesh_force_mean, te.mesh_force_max, te.dynamic_factor);
      if (const std::string note = DynamicFactorNote(te); !note.empty()) {
        fmt::print("                      (dynamic factor {})\n", note);
      }
      fmt::print(
          "  rattle              {}: {:.3f} drive / {:.3f} back impacts per mesh cycle, "
          "impact velocity RMS {:.4f} m/s, separated {:.1f} % of the time\n",
          RattleRegimeName(rattle.regime), rattle.drive_impacts_per_cycle,
          rattle.back_impacts_per_cycle, rattle.impact_velocity_rms,
          100.0 * rattle.separation_fraction);
      fmt::print(
          "  wheel acceleration  RMS {:.1f} rad/s², {:.2f}x the same gearbox without backlash\n",
          rattle.wheel_acceleration_rms, rattle.acceleration_ratio);
      if (!sideband_rows.empty()) {
        fmt::print("  TE mesh harmonics   {}(sidebands in --json, over {})\n",
                   MeshHarmonicsText(sideband_rows), Count(window, "mesh cycle", "mesh cycles"));
      }
      if (!op.cycles_note.empty()) fmt::print("  note: {}\n", op.cycles_note);
      for (const std::string& w : op.warnings) {
        if (std::ranges::find(said_before_run, w) == said_before_run.end()) {
          fmt::print("  warning: {}\n", w);
        }
      }
      if (s.trajectory_truncated) {
        fmt::print(
            "  note: sample storage bound reached: statistics cover every recorded cycle, the "
            "stored samples (and spectra) stop at the bound\n");
      }
    }
    return summary.status == SolverStatus::kSuccess ? 0 : 1;
  });
}

}  // namespace gearnvh::app
