#include "simulate_train.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>
#include <optional>

#include "finite_results.h"
#include "gearnvh/model/gear_train.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/train_lyapunov.h"
#include "gearnvh/solver/train_statistics.h"
#include "gearnvh/solver/train_stepper.h"
#include "output_folder.h"

namespace gearnvh::app {
namespace {

constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);
constexpr int kSamplesPerCycle = 32;

const char* StatusName(TrainStepperSummary::Info info) {
  return info == TrainStepperSummary::Info::kSuccess ? "success" : "too many events";
}

// What the train solver does not model yet, said once per run.
std::vector<std::string> TrainWarnings(const TrainSpec& spec, const GearTrain& train) {
  std::vector<std::string> out = train.warnings;
  for (size_t i = 0; i < spec.meshes.size(); ++i) {
    if (spec.meshes[i].mesh.friction_coefficient > 0.0) {
      out.push_back(fmt::format(
          "meshes[{}].friction_coefficient = {:g}: tooth friction is not modelled by the train "
          "solver yet (ignored)",
          i, spec.meshes[i].mesh.friction_coefficient));
    }
  }
  for (const TrainGear& g : spec.gears) {
    if (g.gear.runout || !g.gear.pitch_errors.empty()) {
      out.push_back("gears." + g.name +
                    ": runout and pitch errors are not modelled by the train solver yet (ignored)");
    }
  }
  return out;
}

// The K largest exponents over the same transient and cycles as the run (a second run).
TrainLyapunovSummary RunLyapunov(const TrainTables& tables, const Eigen::VectorXd& z0,
                                 const std::vector<ContactState>& states0, int exponents,
                                 long transient, long cycles, bool on_terminal) {
  TrainLyapunovOptions options;
  options.exponents = exponents;
  options.transient_cycles = transient;
  options.alignment_cycles = std::min<long>(options.alignment_cycles, cycles / 4);
  options.cycles = cycles;
  if (on_terminal) {
    options.progress = [](double fraction) {
      fmt::print(stderr, "\rlyapunov: {:3.0f}%", 100.0 * fraction);
    };
  }
  TrainLyapunovSummary out = EstimateTrainLyapunov(tables, z0, states0, options);
  if (on_terminal) fmt::print(stderr, "\n");
  return out;
}

// Infinity (no positive exponent: no horizon) as null.
nlohmann::json FiniteOrNull(double x) { return std::isfinite(x) ? nlohmann::json(x) : nullptr; }

nlohmann::json LyapunovJson(const TrainLyapunovSummary& l) {
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

int SimulateTrain(const SimulateOptions& options, const TrainSpec& spec) {
  const Tier tier = options.tier ? ParseTier(*options.tier) : spec.analysis.tier;
  if (tier != Tier::kTier1) {
    throw InputError(options.tier ? "--tier" : "analysis.tier", 0,
                     options.tier ? *options.tier : TierName(tier),
                     "gear trains run on tier 1 (one torsional DOF per body) for now");
  }
  if (options.method != "fused" && options.method != "v3") {
    throw InputError("--method", 0, options.method,
                     "gear trains run the closed-form event locator (v3) only for now");
  }
  if (options.uff) {
    throw InputError("--uff", 0, *options.uff, "UFF export is not available for gear trains yet");
  }
  const long cycles = options.cycles.value_or(spec.analysis.cycles);
  const long transient = options.transient.value_or(spec.analysis.transient_cycles);
  if (cycles < 1) throw InputError("--cycles", 0, std::to_string(cycles), "must be >= 1");
  if (transient < 0) throw InputError("--transient", 0, std::to_string(transient), "must be >= 0");
  const TrainLyapunovOptions lyapunov_defaults;
  if (options.lyapunov && cycles < lyapunov_defaults.blocks) {
    throw InputError("--cycles", 0, std::to_string(cycles),
                     "must be >= " + std::to_string(lyapunov_defaults.blocks) +
                         " with --lyapunov (one block per standard-error block)");
  }
  const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", false);

  const GearTrain train = BuildGearTrain(spec);
  const TrainTables tables = BuildTrainTables(spec, train);
  if (options.lyapunov && *options.lyapunov > 2 * tables.n - 2) {
    throw InputError("--lyapunov", 0, std::to_string(*options.lyapunov),
                     "must be <= 2n - 2 = " + std::to_string(2 * tables.n - 2) +
                         " for this train (" + std::to_string(tables.n) +
                         " bodies; the free rotation's two neutral directions are removed)");
  }
  const std::vector<std::string> warnings = TrainWarnings(spec, train);
  // cycles and transient_cycles count cycles of the first mesh in the file.
  const double period = tables.meshes.front().period;
  const double start = static_cast<double>(transient) * period;
  const double end = start + static_cast<double>(cycles) * period;

  const auto [z0, states0] = TrainStaticState(tables);
  TrainStepperOptions solver;
  TrainStepper stepper(tables, solver, z0, states0);
  TrainRecorder recorder(tables, kSamplesPerCycle, start);
  const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
  const auto wall_start = std::chrono::steady_clock::now();
  constexpr int kChunks = 100;
  bool ok = true;
  for (int c = 1; c <= kChunks && ok; ++c) {
    ok = stepper.Run(end * c / kChunks, &recorder);
    if (on_terminal) {
      fmt::print(stderr, "\rsimulate: {:3d}% ({:.0f}/{} mesh cycles of {})", c,
                 stepper.time() / period, transient + cycles, tables.meshes.front().name);
    }
  }
  if (on_terminal) fmt::print(stderr, "\n");
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  const TrainStepperSummary s = stepper.summary();
  const TrainStatistics stats = recorder.Result();
  std::optional<TrainLyapunovSummary> lyapunov;
  if (options.lyapunov && ok) {
    lyapunov = RunLyapunov(tables, z0, states0, *options.lyapunov, transient, cycles, on_terminal);
  }

  nlohmann::json doc;
  doc["schema"] = "gearnvh/2";
  doc["name"] = spec.name;
  doc["file"] = options.file;
  doc["tier"] = TierName(tier);
  doc["state_dim"] = tables.m;
  doc["method"] = "v3";
  doc["input_speed"] = {{"rad_s", spec.operating.speed}, {"rpm", spec.operating.speed * kRpm}};
  doc["common_period_s"] = tables.common_period;
  doc["warnings"] = warnings;
  doc["summary"] = {{"status", StatusName(s.info)},
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
                    {"samples", stats.samples},
                    {"cache",
                     {{"bytes", s.cache.bytes},
                      {"peak_bytes", s.cache.peak_bytes},
                      {"limit_bytes", solver.tables.cache_limit_bytes},
                      {"tuples", s.cache.tuples},
                      {"hits", s.cache.hits},
                      {"misses", s.cache.misses},
                      {"evictions", s.cache.evictions},
                      {"ill_conditioned", s.cache.ill_conditioned}}}};
  nlohmann::json meshes = nlohmann::json::array();
  for (size_t i = 0; i < stats.meshes.size(); ++i) {
    const TrainMeshStatistics& m = stats.meshes[i];
    const double mesh_cycles = stats.recorded_time / tables.meshes[i].period;
    meshes.push_back(
        {{"name", m.name},
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
           {"impact_velocity_max", m.impact_velocity_max}}}});
  }
  doc["meshes"] = meshes;
  nlohmann::json loose = nlohmann::json::array();
  for (const TrainLooseGearStatistics& g : stats.loose_gears) {
    loose.push_back({{"name", g.name},
                     {"rank", g.rank},
                     {"rattle_index", g.rattle_index},
                     {"impacts", g.impacts}});
  }
  doc["loose_gears"] = loose;
  if (lyapunov) doc["lyapunov"] = LyapunovJson(*lyapunov);
  RequireFinite(doc, "simulate");
  if (out) {
    out->Write("results.json", doc.dump(2) + "\n");
    out->Commit();
  }
  if (options.json) {
    std::cout << doc.dump(2) << "\n";
  } else {
    fmt::print("{}  ({}), gear train, {}: {} bodies, {} meshes, state dimension {}\n", spec.name,
               options.file, TierName(tier), tables.n, tables.meshes.size(), tables.m);
    fmt::print("  operating point     input shaft {} at {:.4g} rpm\n", spec.operating.input_shaft,
               spec.operating.speed * kRpm);
    fmt::print("  status              {}\n", StatusName(s.info));
    fmt::print("  simulated           {:.4f} s ({} + {} cycles of {}), {:.4f} s recorded\n",
               s.simulated_time, transient, cycles, tables.meshes.front().name,
               stats.recorded_time);
    fmt::print("  contact events      {} ({} simultaneous, {} grazing)\n", s.events,
               s.simultaneous_events, s.grazing);
    fmt::print("  wall time           {:.4f} s: {:.2f}x real time\n", wall,
               wall > 0.0 ? s.simulated_time / wall : 0.0);
    fmt::print(
        "  table cache         {:.1f} MiB held (peak {:.1f} MiB), {} tuples, {} built, {} "
        "evicted, {} on the dense path\n",
        s.cache.bytes / 1048576.0, s.cache.peak_bytes / 1048576.0, s.cache.tuples, s.cache.misses,
        s.cache.evictions, s.cache.ill_conditioned);
    fmt::print("\n  {:<10}{:>12}{:>12}{:>12}{:>14}{:>9}{:>9}{:>11}\n", "mesh", "TE mean µm",
               "TE RMS µm", "TE p-p µm", "force max N", "drive", "back", "separated");
    for (const TrainMeshStatistics& m : stats.meshes) {
      fmt::print("  {:<10}{:>12.4f}{:>12.4f}{:>12.4f}{:>14.2f}{:>9}{:>9}{:>10.1f}%\n", m.name,
                 m.te_mean * 1e6, m.te_rms * 1e6, m.te_peak_to_peak * 1e6, m.force_max,
                 m.drive_impacts, m.back_impacts, 100.0 * m.free_time_fraction);
    }
    if (!stats.loose_gears.empty()) {
      fmt::print("\n  loose gears by rattle index (RMS angular acceleration):\n");
      for (const TrainLooseGearStatistics& g : stats.loose_gears) {
        fmt::print("    {}. {:<8}{:>12.1f} rad/s²{:>10} impacts\n", g.rank, g.name, g.rattle_index,
                   g.impacts);
      }
    }
    fmt::print(
        "  (TE is measured from the nominal rigid rotation, so its mean includes the mesh's half "
        "backlash b:\n   drive contact closes the gap at TE = b; b per mesh in µm:");
    for (size_t i = 0; i < stats.meshes.size(); ++i)
      fmt::print(" {} {:.4g}", stats.meshes[i].name, tables.meshes[i].half_backlash * 1e6);
    fmt::print(")\n");
    fmt::print(
        "  (TE, force and rattle index from {} uniform samples, {} per cycle of the fastest "
        "mesh; impacts and separation from the exact events)\n",
        stats.samples, kSamplesPerCycle);
    if (lyapunov) PrintLyapunov(*lyapunov);
    for (const std::string& w : warnings) fmt::print("  warning: {}\n", w);
  }
  const bool lyapunov_ok = !lyapunov || lyapunov->info == TrainLyapunovSummary::Info::kSuccess;
  return s.info == TrainStepperSummary::Info::kSuccess && lyapunov_ok ? 0 : 1;
}

}  // namespace gearnvh::app
