#include "sweep_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "atlas_documents.h"
#include "atomic_file.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/parallel_for.h"
#include "gearnvh/analysis/run_memory.h"
#include "gearnvh/analysis/speed_sweep.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/input_error.h"
#include "mpi_context.h"
#include "output_folder.h"
#include "rank_gather.h"
#include "simulate_command.h"
#include "train_command_options.h"
#include "train_sweep_command.h"
#include "uff_export.h"

namespace gearnvh::app {

namespace {

nlohmann::json NumberOrNull(double v) {
  return std::isnan(v) ? nlohmann::json() : nlohmann::json(v);
}

nlohmann::json PointJson(const SpeedPoint& p) {
  return {{"speed_rad_s", p.speed_rad_s},
          {"speed_rpm", p.speed_rpm},
          {"ok", p.ok},
          {"message", p.message},
          {"te_rms", ResultOrNull(p.ok, p.te_rms)},
          {"te_peak_to_peak", ResultOrNull(p.ok, p.te_peak_to_peak)},
          {"events_per_cycle", ResultOrNull(p.ok, p.events_per_cycle)},
          {"drive", ResultOrNull(p.ok, p.drive_impacts_per_cycle)},
          {"back", ResultOrNull(p.ok, p.back_impacts_per_cycle)},
          {"regime", p.ok ? RattleRegimeName(p.regime) : ""},
          {"matvec_per_cycle", p.matvec_per_cycle},
          {"real_time_ratio", p.real_time_ratio},
          {"amplitude_m", p.amplitude_m}};
}

// `sweep --uff FILE`: the order tracks of the speeds that succeeded, with a note on stderr when
// some failed; nothing (FILE unchanged, said) when there is nothing to write.
void WriteSweepUff(const std::string& path, const std::vector<UffFunction>& tracks, int failed,
                   size_t speeds) {
  if (!WriteUffFile(path, tracks)) {
    fmt::print(stderr,
               "note: --uff {}: not written ({} unchanged): no order track to write ({} of {} "
               "speeds failed; a track needs 2 or more evenly spaced speeds)\n",
               path, path, failed, speeds);
  } else if (failed > 0) {
    fmt::print(stderr,
               "note: --uff {}: the order tracks hold the {} speeds that succeeded; {} left out "
               "(a track is split where they were)\n",
               path, speeds - static_cast<size_t>(failed),
               Count(failed, "failed speed is", "failed speeds are"));
  }
}

// A speed no rank returned.
template <typename Point>
void LoseSpeed(Point& p) {
  p.ok = false;
  p.message = "lost: no rank returned this speed";
}

SpeedPoint PointFromJson(const nlohmann::json& j) {
  SpeedPoint p;
  p.speed_rad_s = j.at("speed_rad_s").get<double>();
  p.speed_rpm = j.at("speed_rpm").get<double>();
  p.ok = j.at("ok").get<bool>();
  p.message = j.at("message").get<std::string>();
  p.te_rms = ResultFromJson(j.at("te_rms"));
  p.te_peak_to_peak = ResultFromJson(j.at("te_peak_to_peak"));
  p.events_per_cycle = ResultFromJson(j.at("events_per_cycle"));
  p.drive_impacts_per_cycle = ResultFromJson(j.at("drive"));
  p.back_impacts_per_cycle = ResultFromJson(j.at("back"));
  if (p.ok) p.regime = RegimeFromJson(j.at("regime"));
  p.matvec_per_cycle = j.at("matvec_per_cycle").get<double>();
  p.real_time_ratio = j.at("real_time_ratio").get<double>();
  p.amplitude_m = j.at("amplitude_m").get<std::vector<double>>();
  return p;
}

// `sweep` on a gear train: the train solver per speed (train_sweep.h), under mpirun the speeds
// split across ranks as the pair's.
int SweepTrain(const SweepOptions& options, const TrainSpec& spec) {
  const int rank = MpiContext::Rank();
  TrainSweepOptions sweep = PlanTrainSweep(options, spec);
  sweep.ranks = MpiContext::Size();  // each rank's cost is its share of the speeds
  sweep.before_run_warning = [rank](const std::string& w) {
    if (rank == 0) fmt::print(stderr, "warning: {}\n", w);
  };
  const Tier tier = sweep.tier;
  const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", true);
  const bool on_terminal = rank == 0 && ::isatty(STDERR_FILENO) != 0;
  TrainSweepProgress progress;
  if (on_terminal) {
    progress = [](int done, int total) {
      fmt::print(stderr, "\rsweep: {:3d}% ({}/{} speeds)", 100 * done / total, done, total);
    };
  }
  const std::vector<bool> skip =
      OtherRanksItems(static_cast<size_t>(spec.analysis.speed_sweep.points));
  TrainSweepResult result = RunTrainSweep(spec, sweep, progress, skip);
  if (on_terminal) fmt::print(stderr, "\n");
  if (!GatherItemsToRoot(result.points, skip, TrainSweepPointJson, TrainSweepPointFromJson,
                         LoseSpeed<TrainSweepPoint>)) {
    return 0;
  }
  NameLooseGears(result);
  nlohmann::json doc = TrainSweepDocument(result, spec, options.file, sweep);
  RequireFinite(doc, "sweep");
  if (out) {
    out->Write("meshes.csv", TrainMeshesCsv(result));
    out->Write("loose_gears.csv", TrainLooseGearsCsv(result));
    if (!spec.couplings.empty()) out->Write("couplings.csv", TrainCouplingsCsv(result));
    out->Write("waterfall.csv", WaterfallCsv(MeshWaterfalls(result), result.mesh_names));
    out->Write("sweep.json", doc.dump(1) + "\n");
    out->Commit();
  }
  if (options.uff) {
    WriteSweepUff(*options.uff, TrainSweepOrderTracksUff(spec, result), result.failed(),
                  result.points.size());
  }
  if (options.json) {
    std::cout << doc.dump(1) << "\n";
  } else {
    fmt::print("{}  ({}), gear train, {}: speed sweep of {}, {} speeds, {} each\n", spec.name,
               options.file, TierName(tier), spec.operating.input_shaft, result.points.size(),
               Count(sweep.cycles, "cycle of " + result.mesh_names.front(),
                     "cycles of " + result.mesh_names.front()));
    PrintTrainSweep(result, spec.operating.speed_unit);
  }
  if (result.failed() > 0) {
    std::cerr << "error: " << result.failed() << " of " << result.points.size()
              << " speeds failed (listed in the output)\n";
    return 1;
  }
  return 0;
}

}  // namespace

nlohmann::json SweepJson(const SpeedSweepResult& r, double mesh_order) {
  nlohmann::json speeds = nlohmann::json::array();
  for (const SpeedPoint& p : r.points) speeds.push_back(p.speed_rpm);
  nlohmann::json modes = nlohmann::json::array();
  for (size_t k = 0; k < r.campbell.frequency_hz.size(); ++k) {
    nlohmann::json f = nlohmann::json::array(), mac = nlohmann::json::array(),
                   zeta = nlohmann::json::array();
    for (size_t s = 0; s < r.campbell.frequency_hz[k].size(); ++s) {
      f.push_back(NumberOrNull(r.campbell.frequency_hz[k][s]));
      mac.push_back(NumberOrNull(r.campbell.mac[k][s]));
      zeta.push_back(NumberOrNull(r.campbell.damping_ratio[k][s]));
    }
    const ModeInfo& info = r.campbell.modes[k];
    modes.push_back({{"mode", k + 1},
                     {"label", info.Label()},
                     {"type", ModeTypeName(info.type)},
                     {"whirl", WhirlName(info.whirl)},
                     {"energy_fraction",
                      {{"torsional", info.energy_fraction[0]},
                       {"lateral", info.energy_fraction[1]},
                       {"axial", info.energy_fraction[2]}}},
                     {"frequency_hz", f},
                     {"damping_ratio", zeta},
                     {"mac", mac}});
  }
  nlohmann::json orders = nlohmann::json::array();
  for (const OrderLine& o : r.campbell.orders)
    orders.push_back({{"label", o.label}, {"order", o.order}});
  nlohmann::json critical = nlohmann::json::array();
  for (const CriticalSpeed& c : r.campbell.critical_speeds) {
    critical.push_back({{"order", c.order},
                        {"mode", c.mode + 1},
                        {"mode_label", r.campbell.modes[static_cast<size_t>(c.mode)].Label()},
                        {"speed_rpm", c.speed_rpm},
                        {"frequency_hz", c.frequency_hz}});
  }
  nlohmann::json points = nlohmann::json::array(), amplitude = nlohmann::json::array();
  for (const SpeedPoint& p : r.points) {
    points.push_back({{"speed_rpm", p.speed_rpm},
                      {"ok", p.ok},
                      {"message", p.message},
                      {"te_rms", ResultOrNull(p.ok, p.te_rms)},
                      {"te_peak_to_peak", ResultOrNull(p.ok, p.te_peak_to_peak)},
                      {"events_per_cycle", ResultOrNull(p.ok, p.events_per_cycle)},
                      {"drive_impacts_per_cycle", ResultOrNull(p.ok, p.drive_impacts_per_cycle)},
                      {"back_impacts_per_cycle", ResultOrNull(p.ok, p.back_impacts_per_cycle)},
                      {"regime", p.ok ? RattleRegimeName(p.regime) : ""},
                      {"matvec_per_cycle", p.matvec_per_cycle},
                      {"real_time_ratio", p.real_time_ratio}});
    amplitude.push_back(p.amplitude_m);
  }
  return {{"speeds_rpm", speeds},
          {"failed_speeds", r.failed()},
          {"campbell", {{"modes", modes}, {"orders", orders}, {"critical_speeds", critical}}},
          {"waterfall",
           {{"order_step", r.order_step},
            {"order_bins", r.order_bins},
            {"mesh_order", mesh_order},
            {"points", points},
            {"amplitude_m", amplitude}}}};
}

std::string CampbellCsv(const SpeedSweepResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm,mode,mode_label,frequency_hz,damping_ratio,mac\n";
  for (size_t k = 0; k < r.campbell.frequency_hz.size(); ++k) {
    for (size_t s = 0; s < r.points.size(); ++s) {
      os << r.points[s].speed_rpm << ',' << k + 1 << ",\"" << r.campbell.modes[k].Label() << "\","
         << r.campbell.frequency_hz[k][s] << ',' << r.campbell.damping_ratio[k][s] << ','
         << r.campbell.mac[k][s] << '\n';
    }
  }
  return os.str();
}

std::string CriticalCsv(const SpeedSweepResult& r) {
  std::ostringstream os;
  os.precision(12);
  os << "order,mode,mode_label,speed_rpm,frequency_hz\n";
  for (const CriticalSpeed& c : r.campbell.critical_speeds) {
    os << c.order << ',' << c.mode + 1 << ",\""
       << r.campbell.modes[static_cast<size_t>(c.mode)].Label() << "\"," << c.speed_rpm << ','
       << c.frequency_hz << '\n';
  }
  return os.str();
}

std::string WaterfallCsv(const std::vector<WaterfallView>& waterfalls,
                         const std::vector<std::string>& names) {
  std::ostringstream os;
  os.precision(12);
  os << (names.empty() ? "speed_rpm,order,frequency_hz,amplitude_m\n"
                       : "speed_rpm,mesh,order,frequency_hz,amplitude_m\n");
  const size_t speeds = waterfalls.empty() ? 0 : waterfalls.front().speed_rpm.size();
  for (size_t s = 0; s < speeds; ++s) {
    for (size_t i = 0; i < waterfalls.size(); ++i) {
      const WaterfallView& w = waterfalls[i];
      if (w.rows[s] == nullptr) continue;
      const double rpm = w.speed_rpm[s];
      for (size_t k = 0; k < w.rows[s]->size(); ++k) {
        const double order = static_cast<double>(k) * w.order_step;
        os << rpm << ',';
        if (!names.empty()) os << names[i] << ',';
        os << order << ',' << order * rpm / 60.0 << ',' << (*w.rows[s])[k] << '\n';
      }
    }
  }
  return os.str();
}

namespace {

// Before the run: the speeds a rank has in flight at once each hold their recording. Under mpirun
// every rank checks its own speeds against its node's memory, shared by the ranks there, and all
// refuse together with the first rank's refusal (rank 0 alone prints); the warning is rank 0's.
std::string CheckSweepMemory(const SweepOptions& options, const SpeedSweepOptions& sweep,
                             const GearboxSpec& spec, int rank, int ranks) {
  const auto my_speeds =
      static_cast<size_t>((spec.analysis.speed_sweep.points + ranks - 1 - rank) / ranks);
  const RunMemory need = SpeedSweepMemory(sweep, my_speeds);
  const std::optional<MemoryLimit> limit =
      AvailableMemoryOnEveryRank(ParallelWorkers(my_speeds, sweep.threads) - 1);
  const std::string option =
      options.cycles ? "--cycles" : "the default cycles per speed (set by --cycles)";
  const std::string value = std::to_string(sweep.cycles);
  const std::string remedy = "fewer recorded cycles or --jobs need less";
  std::string refusal = MemoryRefusal(need, limit, remedy);
  if (!refusal.empty() && ranks > 1) refusal = fmt::format("on rank {}, {}", rank, refusal);
  refusal = MpiContext::FirstNonEmpty(refusal);
  if (!refusal.empty()) throw InputError(option, 0, value, refusal);
  return CheckRunMemory(need, limit, option, value, remedy);
}

}  // namespace

int RunSweep(const SweepOptions& options) {
  const int code = RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    if (!loaded.sweep_note.empty() && MpiContext::Rank() == 0) {
      std::cerr << "note: " << loaded.sweep_note << "\n";
    }
    if (loaded.schema == 2) return SweepTrain(options, loaded.train);
    const std::unique_ptr<OutputFolder> out = OpenOutputFolder(options.out, "--out", true);
    const GearboxSpec spec = std::move(*loaded.pair);
    const Tier tier = options.tier ? ParseTier(*options.tier) : spec.analysis.tier;
    SpeedSweepOptions sweep;
    sweep.cycles = options.cycles.value_or(sweep.cycles);
    sweep.transient_cycles = options.transient.value_or(sweep.transient_cycles);
    RequireCycleCounts(sweep.cycles, 2, sweep.transient_cycles);
    sweep.waterfall_cycles = std::min(sweep.waterfall_cycles, sweep.cycles - 1);
    RequireRunLengthOfOptions(loaded.train, spec.analysis.speed_sweep.from, sweep.cycles,
                              sweep.transient_cycles, options.cycles, options.transient);
    sweep.threads = options.jobs;
    sweep.method = options.method;
    const ComponentModel model = BuildComponentModel(spec);
    RequirePairTier(model, tier, options.tier);
    const ReducedModel reduced = ReduceModel(model, tier);
    const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
    const std::string memory_warning = CheckSweepMemory(options, sweep, spec, rank, ranks);
    if (!memory_warning.empty() && rank == 0) {
      fmt::print(stderr, "warning: {}\n", memory_warning);
    }
    const bool on_terminal = ::isatty(STDERR_FILENO) != 0;
    SweepProgress progress;
    if (on_terminal) {
      progress = [](int done, int total) {
        fmt::print(stderr, "\rsweep: {:3d}% ({}/{} speeds)", 100 * done / total, done, total);
      };
    }
    // Under mpirun the speeds are split across ranks (round robin) and rank 0 gathers them.
    const std::vector<bool> skip =
        OtherRanksItems(static_cast<size_t>(spec.analysis.speed_sweep.points));
    SpeedSweepResult result =
        RunSpeedSweep(spec, model, reduced, sweep, rank == 0 ? progress : SweepProgress{}, skip);
    if (on_terminal) fmt::print(stderr, "\n");
    if (!GatherItemsToRoot(result.points, skip, PointJson, PointFromJson, LoseSpeed<SpeedPoint>))
      return 0;

    nlohmann::json doc = SweepJson(result, spec.pinion.teeth);
    doc["name"] = spec.name;
    doc["file"] = options.file;
    doc["tier"] = reduced.name;
    doc["cycles_per_speed"] = sweep.cycles;
    doc["transient_cycles"] = sweep.transient_cycles;
    const int failed = result.failed();
    RequireFinite(doc, "sweep");
    if (out) {
      out->Write("campbell.csv", CampbellCsv(result));
      out->Write("critical_speeds.csv", CriticalCsv(result));
      out->Write("waterfall.csv", WaterfallCsv({PairWaterfall(result)}));
      out->Write("sweep.json", doc.dump(1) + "\n");
      out->Commit();
    }
    if (options.uff) {
      WriteSweepUff(*options.uff, SweepOrderTracksUff(spec, result), failed, result.points.size());
    }
    if (options.json) {
      std::cout << doc.dump(1) << "\n";
    } else {
      fmt::print("{}  ({}), {}: speed sweep, {} speeds, {} each\n", spec.name, options.file,
                 reduced.name, result.points.size(),
                 Count(sweep.cycles, "mesh cycle", "mesh cycles"));
      // Speeds in the unit the file wrote operating.speed in (the JSON and CSV keep rpm).
      const DisplayUnit& unit = spec.operating.speed_unit;
      auto shown = [&unit](double rpm) {
        return rpm * (2.0 * std::numbers::pi / 60.0) * unit.per_si;
      };
      fmt::print("  {:>8}  {:>10}  {:>12}  {:>14}  {}\n", unit.symbol, "TE RMS µm", "events/cycle",
                 "1x mesh TE µm", "regime");
      const size_t mesh_bin =
          static_cast<size_t>(std::lround(spec.pinion.teeth / result.order_step));
      for (const SpeedPoint& p : result.points) {
        if (!p.ok) {
          fmt::print("  {:8.6g}  failed: {}\n", shown(p.speed_rpm), p.message);
          continue;
        }
        const double mesh = mesh_bin < p.amplitude_m.size() ? p.amplitude_m[mesh_bin] : 0.0;
        fmt::print("  {:8.6g}  {:10.4f}  {:12.3f}  {:14.4f}  {}\n", shown(p.speed_rpm),
                   p.te_rms * 1e6, p.events_per_cycle, mesh * 1e6, RattleRegimeName(p.regime));
      }
      fmt::print("  critical speeds (order line x tracked mode):\n");
      for (const CriticalSpeed& c : result.campbell.critical_speeds) {
        fmt::print("    {:8.6g} {}  {:>9}  mode {} ({})  {:.1f} Hz\n", shown(c.speed_rpm),
                   unit.symbol, c.order, c.mode + 1,
                   result.campbell.modes[static_cast<size_t>(c.mode)].Label(), c.frequency_hz);
      }
      if (result.campbell.critical_speeds.empty()) fmt::print("    none in the sweep range\n");
    }
    if (failed > 0) {
      std::cerr << "error: " << failed << " of " << result.points.size()
                << " speeds failed (listed in the output)\n";
      return 1;
    }
    return 0;
  });
  return MpiContext::BroadcastInt(code);
}

}  // namespace gearnvh::app
