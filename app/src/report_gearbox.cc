#include "report_gearbox.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <optional>
#include <sstream>

#include "atlas_documents.h"
#include "atomic_file.h"
#include "check_command.h"
#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/operating_point.h"
#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/periodic_orbit.h"
#include "report_figures.h"
#include "report_page.h"
#include "report_sweep_figures.h"
#include "report_whine.h"
#include "report_train.h"
#include "result_documents.h"
#include "sweep_command.h"
#include "tiers_command.h"
#include "uff_export.h"

namespace gearnvh::app {

namespace fs = std::filesystem;

namespace {

std::string TraceCsv(const Trajectory& t, size_t last) {
  std::ostringstream os;
  os.precision(12);
  os << "time_s,te_m,te_rate_m_s,mesh_force_n,wheel_acceleration_rad_s2,contact\n";
  const size_t first = t.samples.size() > last ? t.samples.size() - last : 0;
  for (size_t i = first; i < t.samples.size(); ++i) {
    const TrajectorySample& s = t.samples[i];
    os << s.time << ',' << s.te << ',' << s.te_rate << ',' << s.mesh_force << ','
       << s.wheel_acceleration << ',' << ContactStateName(s.state) << '\n';
  }
  return os.str();
}

std::string SpectrumCsv(const AmplitudeSpectrum& s) {
  std::ostringstream os;
  os.precision(12);
  os << "frequency_hz,amplitude_m\n";
  for (size_t k = 0; k < s.amplitude.size(); ++k) {
    os << static_cast<double>(k) * s.bin_hz << ',' << s.amplitude[k] << '\n';
  }
  return os.str();
}

std::string SidebandsCsv(const std::vector<SidebandRow>& rows) {
  std::ostringstream os;
  os.precision(12);
  os << "label,frequency_hz,amplitude_m,db_re_1um\n";
  for (const SidebandRow& r : rows) {
    os << r.label << ',' << r.frequency_hz << ',' << r.amplitude << ',' << r.db_re_1um << '\n';
  }
  return os.str();
}

std::string MeshCycleCsv(const ComponentModel& model) {
  std::ostringstream os;
  os.precision(12);
  os << "cycle_fraction,stiffness_drive_n_m,stiffness_back_n_m,lste_m,loaded_pairs\n";
  for (size_t k = 0; k < model.cycle.tau.size(); ++k) {
    os << model.cycle.tau[k] << ',' << model.cycle.drive[k].stiffness << ','
       << model.cycle.back[k].stiffness << ',' << model.cycle.drive[k].lste << ','
       << model.cycle.drive[k].loaded_pairs << '\n';
  }
  return os.str();
}

}  // namespace

void ThrowUnlessDrawn(const std::string& name, const render::RenderStatus& status) {
  if (status.ok) return;
  if (status.error_number != 0) {
    throw IoError("image " + name + ": " + status.message, std::strerror(status.error_number));
  }
  throw std::runtime_error("image " + name + ": " + status.message);
}

GearboxEntry BuildGearboxReport(const std::string& file, const std::filesystem::path& folder,
                                const ReportCommandOptions& o, int threads,
                                const StageProgress& stage,
                                const std::optional<MemoryLimit>& memory) {
  auto counted = [&stage](const char* what, const char* unit) {
    return [&stage, what, unit](long done, long total) {
      stage(fmt::format("{} {}/{} {}", what, done, total, unit));
    };
  };
  const auto start = std::chrono::steady_clock::now();
  GearboxEntry entry;
  entry.file = file;
  entry.folder = folder.filename().string();
  config::SourceLocations where;
  try {
    config::LoadedGearbox loaded = config::LoadAnyGearboxFile(file);
    where = loaded.locations;
    if (loaded.schema == 2) {
      entry.name = loaded.train.name;
      fs::create_directories(folder);
      entry.summary = BuildTrainReport(file, folder, o, threads, stage, loaded.train, memory);
      entry.ok = true;
      entry.wall_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return entry;
    }
    if (stage) stage("model and modal tiers");
    const GearboxSpec spec = std::move(*loaded.pair);
    entry.name = spec.name;
    fs::create_directories(folder);
    const ComponentModel model = BuildComponentModel(spec);
    const ModalSummary modes = FullModelFrequencies(model, kReportedModes);
    const std::vector<ReducedModel> tiers = ReduceAvailableTiers(model);
    const nlohmann::json check = CheckReport(spec, model, modes, tiers);
    const Tier tier = spec.analysis.tier;
    SolverOptions solver;
    solver.cycles = spec.analysis.cycles;
    solver.transient_cycles = spec.analysis.transient_cycles;
    const OperatingPointAnalysis op = AnalyseOperatingPoint(
        spec, model, tier, solver,
        stage ? ProgressCallback(counted("operating point", "mesh cycles")) : ProgressCallback(),
        {}, [&](RunMemory& need) {
          need.parts.push_back(OperatingPointUffMemory(need.recorded_samples));  // results.uff
          return CheckRunMemory(need, memory, "analysis.cycles", std::to_string(solver.cycles));
        });
    if (op.result.summary.status != SolverStatus::kSuccess) {
      throw std::runtime_error("operating point: " + op.result.summary.message);
    }
    const ReducedModel reduced = ReduceModel(model, tier);
    SpeedSweepOptions sweep_options;
    sweep_options.cycles = 256;
    sweep_options.transient_cycles = 100;
    sweep_options.waterfall_cycles = 255;
    sweep_options.threads = threads;
    const SpeedSweepResult sweep =
        RunSpeedSweep(spec, model, reduced, sweep_options,
                      stage ? SweepProgress(counted("speed sweep", "speeds")) : SweepProgress());
    std::optional<AtlasResult> atlas;
    AtlasOptions atlas_options;
    atlas_options.input_error_message = UserWording({}, PairAxisValueText(spec));
    if (o.atlas && spec.analysis.atlas_x && spec.analysis.atlas_y) {
      AtlasAxis x = *spec.analysis.atlas_x, y = *spec.analysis.atlas_y;
      x.range.points = std::min(x.range.points, 12);
      y.range.points = std::min(y.range.points, 12);
      atlas_options.tier = tier;
      atlas_options.transient_cycles = 270;
      atlas_options.cycles = 540;
      atlas_options.threads = threads;
      atlas =
          RunChaosAtlas(spec, x, y, atlas_options,
                        stage ? AtlasProgress(counted("chaos atlas", "cells")) : AtlasProgress());
    }
    long base_period = 1;
    try {
      base_period = BasePeriodCycles(op.tables);
    } catch (const InputError&) {
      base_period = 1;  // incommensurate orders: section every mesh cycle
    }

    const std::vector<OrderTrack> mesh_tracks =
        MeshOrderTracks(PairWaterfall(sweep), spec.pinion.teeth, 3);
    const std::vector<OrderTrack> sideband_tracks = LargestSidebandTracks(spec, sweep, 2);

    // Images.
    if (stage) stage("images");
    render::ImageOptions image;
    image.width = o.width;
    image.height = o.height;
    image.dpi = o.dpi;
    render::ImageOptions small = image;
    small.width = std::max(200, o.width * 2 / 3);
    small.height = std::max(150, o.height * 2 / 3);
    std::vector<ReportFigure> figures;
    auto draw = [&](const std::string& name, const std::string& caption,
                    const render::RenderStatus& status) {
      ThrowUnlessDrawn(name, status);
      figures.push_back({name, caption});
    };
    const long trace_cycles = std::clamp<long>(2 * base_period, 4, 64);
    draw("te_trace.png", "Dynamic transmission error at the operating point (exact solution).",
         render::RenderLinePlot(TeTraceFigure(op, trace_cycles), image,
                                (folder / "te_trace.png").string()));
    if (!op.spectrum.amplitude.empty()) {
      draw("spectrum.png",
           "TE spectrum over " + Count(op.sideband_window, "mesh cycle", "mesh cycles") +
               " (whole periods of the engine orders and gear errors) with mesh harmonics and "
               "shaft-order sidebands.",
           render::RenderLinePlot(SpectrumFigure(op), image, (folder / "spectrum.png").string()));
    }
    draw("phase.png",
         "TE against its rate; points: Poincaré section every base period (" +
             Count(base_period, "mesh cycle", "mesh cycles") + ").",
         render::RenderLinePlot(PhaseFigure(op, 256, base_period), image,
                                (folder / "phase.png").string()));
    if (!op.sidebands.empty()) {
      draw(
          "sidebands.png",
          "Mesh harmonics (blue), shaft orders and shaft-order sidebands (vermillion) of the TE at "
          "the operating "
          "point, dB re 1 µm; f1, f2: pinion and wheel shaft frequencies, fm: mesh frequency "
          "(the full list: sidebands.csv and the table below).",
          render::RenderLinePlot(SidebandStemFigure(op), image,
                                 (folder / "sidebands.png").string()));
    }
    draw("campbell.png",
         "Every tracked natural frequency of the linearised tier (drive contact, mean mesh "
         "stiffness, gyroscopic terms) against speed, coloured and labelled by mode type (number "
         "from 1; fw/bw: forward/backward whirl); dashed: order lines; points: critical speeds.",
         render::RenderLinePlot(CampbellFigure(sweep), image, (folder / "campbell.png").string()));
    draw("order_tracks.png",
         "Order tracks from the speed sweep: TE amplitude at mesh orders 1-3 (solid) and the two "
         "largest shaft-order sidebands (dashed), dB re 1 µm (order_tracks.csv).",
         render::RenderLinePlot(OrderTrackFigure(mesh_tracks, sideband_tracks, sweep.speed_scale),
                                image, (folder / "order_tracks.png").string()));
    draw("waterfall.png", "Steady-state TE spectra across the speed sweep (pinion orders).",
         render::RenderHeatMap(WaterfallFigure(sweep), image, (folder / "waterfall.png").string()));
    if (stage) stage("whine");
    const WhineReport whine = BuildWhineReport(TrainOf(spec), tier, threads, folder, image);
    figures.insert(figures.end(), whine.figures.begin(), whine.figures.end());
    std::vector<TierPoint> tier_points;
    for (const ReducedModel& t : tiers) {
      tier_points.push_back(
          {t.name, static_cast<double>(StateDimension(model, t, spec.operating.excitation)),
           TierFrequencyError(t, modes),
           ComplianceErrorVsFull(t.tier, t.compliance_error_vs_full)});
    }
    draw("tiers.png",
         "Modal tiers: the largest error of the lowest natural frequencies and the static mesh "
         "compliance error against the state dimension the solver integrates (run-time cost "
         "per tier: `gearnvh tiers`).",
         render::RenderLinePlot(
             TierComparisonFigure("state dimension (-)", tier_points, "static compliance error"),
             image, (folder / "tiers.png").string()));
    draw("mesh_stiffness.png", "Mesh stiffness over one mesh cycle (potential energy method).",
         render::RenderLinePlot(MeshStiffnessFigure(model), small,
                                (folder / "mesh_stiffness.png").string()));
    draw("load_sharing.png", "Load sharing ratio of each tooth pair over one mesh cycle.",
         render::RenderLinePlot(LoadSharingFigure(model), small,
                                (folder / "load_sharing.png").string()));
    draw("lste.png", "Loaded static transmission error over one mesh cycle.",
         render::RenderLinePlot(LsteFigure(model), small, (folder / "lste.png").string()));
    if (model.cycle.face.modelled()) {
      draw("face_load.png",
           "Load per unit face width across the face under misalignment and lead modifications "
           "(K_Hβ: its peak over the mean; `check` gives the misalignment components).",
           render::RenderLinePlot(FaceLoadFigure({{"mesh", model.cycle.face}}), small,
                                  (folder / "face_load.png").string()));
    }
    if (atlas) {
      draw("atlas_lyapunov.png",
           "Largest Lyapunov exponent per forcing cycle (red: chaotic, blue: regular; strongly "
           "attracting cells are saturated at minus the largest positive value).",
           render::RenderHeatMap(AtlasFigure(*atlas, true, spec), image,
                                 (folder / "atlas_lyapunov.png").string()));
      draw(
          "atlas_rattle.png",
          "Rattle index: impact energy per forcing cycle (log10 J); grey: no impact (index 0) or a "
          "failed cell.",
          render::RenderHeatMap(AtlasFigure(*atlas, false, spec), image,
                                (folder / "atlas_rattle.png").string()));
    }

    // Data files.
    if (stage) stage("data files and pages");
    const size_t per_cycle = op.tables.boundaries.size() - 1;
    WriteFileAtomically((folder / "te_trace.csv").string(),
                        TraceCsv(op.result.trajectory, 256 * per_cycle));
    WriteFileAtomically((folder / "spectrum.csv").string(), SpectrumCsv(op.spectrum));
    WriteFileAtomically((folder / "sidebands.csv").string(), SidebandsCsv(op.sidebands));
    WriteFileAtomically((folder / "mesh_cycle.csv").string(), MeshCycleCsv(model));
    WriteFileAtomically((folder / "campbell.csv").string(), CampbellCsv(sweep));
    WriteFileAtomically((folder / "critical_speeds.csv").string(), CriticalCsv(sweep));
    WriteFileAtomically((folder / "waterfall.csv").string(), WaterfallCsv({PairWaterfall(sweep)}));
    WriteFileAtomically((folder / "order_tracks.csv").string(),
                        OrderTracksCsv(mesh_tracks, sideband_tracks));
    if (atlas) WriteFileAtomically((folder / "atlas.csv").string(), AtlasCsv(*atlas, spec));
    std::vector<UffFunction> uff = OperatingPointUff(spec, op);
    for (UffFunction& f : SweepOrderTracksUff(spec, sweep, static_cast<int>(uff.size()) + 1)) {
      uff.push_back(std::move(f));
    }
    WriteUffFile((folder / "results.uff").string(), uff);

    nlohmann::json results = {{"name", spec.name},
                              {"file", file},
                              {"check", check},
                              {"operating_point", OperatingPointJson(op)},
                              {"base_period_mesh_cycles", base_period},
                              {"sweep", SweepJson(sweep, spec.pinion.teeth)}};
    if (atlas) results["atlas"] = AtlasJson(*atlas, atlas_options);
    results["whine"] = whine.summary;
    nlohmann::json images = nlohmann::json::array();
    for (const ReportFigure& f : figures)
      images.push_back({{"file", f.file}, {"caption", f.caption}});
    results["images"] = images;
    RequireFinite(results, "results.json");
    WriteFileAtomically((folder / "results.json").string(), results.dump(1) + "\n");

    // Summary for the batch and the page.
    const RattleIndices& r = op.rattle;
    const SolverSummary& s = op.result.summary;
    double first_critical = std::numeric_limits<double>::quiet_NaN();
    for (const CriticalSpeed& c : sweep.campbell.critical_speeds) {
      if (!std::isfinite(first_critical) || c.speed_rpm < first_critical)
        first_critical = c.speed_rpm;
    }
    int chaotic = 0;
    if (atlas) {
      for (const AtlasCell& c : atlas->cells)
        chaotic += c.ok && c.regime == RattleRegime::kChaotic ? 1 : 0;
    }
    entry.summary = {
        {"tier", op.tier_name},
        {"speed_rpm", Rpm(spec.operating.speed)},
        {"torque_nm", spec.operating.torque},
        {"torque_on", TorqueOnName(spec.operating.torque_on)},
        {"speed", Format(spec.operating.speed, spec.operating.speed_unit)},
        {"torque", TorqueText(spec)},
        {"te_rms_um", op.te.rms * 1e6},
        {"te_peak_to_peak_um", op.te.peak_to_peak * 1e6},
        {"regime", RattleRegimeName(r.regime)},
        {"impacts_per_cycle", r.drive_impacts_per_cycle + r.back_impacts_per_cycle},
        {"acceleration_ratio", r.acceleration_ratio},
        {"first_critical_speed_rpm",
         std::isfinite(first_critical) ? nlohmann::json(first_critical) : nlohmann::json()},
        {"chaotic_atlas_cells", atlas ? nlohmann::json(chaotic) : nlohmann::json()},
        {"real_time_ratio", s.real_time_ratio},
        {"failed_speeds", sweep.failed()}};

    WriteFileAtomically((folder / "index.html").string(),
                        GearboxPage({file, spec, model, modes, tiers, op, sweep,
                                     atlas ? &*atlas : nullptr, atlas_options.cycles, figures,
                                     whine.html}));
    entry.ok = true;
  } catch (const IoError& e) {
    entry.error = e.what();
    entry.io_reason = e.reason().empty() ? e.what() : e.reason();
  } catch (const fs::filesystem_error& e) {
    entry.error = e.what();
    entry.io_reason = e.code().message();
  } catch (const InputError& e) {
    entry.error = InputErrorMessage(e, file, where);
  } catch (const NonFiniteResult& e) {
    entry.error = file + ": internal error: " + e.what();
    entry.internal = true;
  } catch (const std::runtime_error& e) {
    entry.error = e.what();
  } catch (const std::exception& e) {
    entry.error = file + ": internal error: " + e.what();
    entry.internal = true;
  }
  entry.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return entry;
}

}  // namespace gearnvh::app
