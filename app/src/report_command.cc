#include "report_command.h"

#include <fmt/format.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <sstream>
#include <thread>

#include "atlas_command.h"
#include "atomic_file.h"
#include "check_command.h"
#include "cleanup_on_exit.h"
#include "command_errors.h"
#include "display_units.h"
#include "config/gearbox_loader.h"
#include "finite_results.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/periodic_orbit.h"
#include "gearnvh/render/display.h"
#include "mpi_context.h"
#include "operating_point.h"
#include "output_folder.h"
#include "report_figures.h"
#include "sweep_command.h"
#include "uff_export.h"

namespace gearnvh::app {

namespace fs = std::filesystem;

namespace {

constexpr const char* kMarker = ".gearnvh-report";
constexpr double kRpm = 60.0 / (2.0 * std::numbers::pi);

std::string Html(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string ReadWholeFileBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

std::string Slug(const std::string& file) {
  std::string stem = fs::path(file).stem().string(), out;
  for (char c : stem) {
    out += std::isalnum(static_cast<unsigned char>(c)) ? static_cast<char>(std::tolower(c)) : '-';
  }
  return out.empty() ? "gearbox" : out;
}

// Marks images that did not load (and counts them in data attributes a headless browser can read).
constexpr const char* kImageCheckScript = R"(<script>
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var broken = images.filter(function (i) { return !(i.complete && i.naturalWidth > 0); });
  document.body.setAttribute('data-images-total', images.length);
  document.body.setAttribute('data-images-broken', broken.length);
  if (broken.length) {
    var p = document.createElement('p');
    p.className = 'warn';
    p.textContent = broken.length + ' image(s) did not load: ' +
        broken.map(function (i) { return i.getAttribute('src'); }).join(', ');
    document.body.insertBefore(p, document.body.firstChild);
  }
});
</script>)";

constexpr const char* kStyle = R"(<style>
body { font-family: sans-serif; margin: 2em auto; max-width: 1250px; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
th { background: #f0f0f0; }
figure { margin: 1em 0 2em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { color: #555; font-size: 0.9em; }
.warning { color: #8a4b00; background: #fff4e0; border-left: 4px solid #e0a030; padding: 0.3em 0.6em; }
.warn { color: #a00; font-weight: bold; }
.ok { color: #070; }
</style>)";

std::string Row(const std::string& name, const std::string& value) {
  return fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", Html(name), Html(value));
}

struct Figure {
  std::string file, caption;
};

struct GearboxEntry {
  std::string file, folder, name;
  bool ok = false;
  bool internal = false;      // failed by a bug (exit 3), not by its input
  bool earlier_kept = false;  // failed now; DIR keeps this folder from an earlier run
  bool from_earlier = false;  // not in this run; kept from an earlier run into DIR
  std::string error;
  nlohmann::json summary;
  double wall_s = 0.0;
};

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

std::string Number(double v, int digits = 4) {
  return std::isfinite(v) ? fmt::format("{:.{}g}", v, digits) : "-";
}

// Reports the stage a gearbox is in ("speed sweep 12/56 speeds"); empty: silent.
using StageProgress = std::function<void(const std::string&)>;

// Everything for one gearbox, written into `folder`.
GearboxEntry BuildGearboxReport(const std::string& file, const fs::path& folder,
                                const ReportCommandOptions& o, int threads,
                                const StageProgress& stage) {
  auto counted = [&stage](const char* what, const char* unit) {
    return [&stage, what, unit](long done, long total) {
      stage(fmt::format("{} {}/{} {}", what, done, total, unit));
    };
  };
  const auto start = std::chrono::steady_clock::now();
  GearboxEntry entry;
  entry.file = file;
  entry.folder = folder.filename().string();
  try {
    if (stage) stage("model and modal tiers");
    const GearboxSpec spec = config::LoadGearboxFile(file);
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
        stage ? ProgressCallback(counted("operating point", "mesh cycles")) : ProgressCallback());
    if (op.result.summary.status != SolverStatus::kSuccess) {
      throw std::runtime_error("operating point: " + op.result.summary.message);
    }
    const ReducedModel reduced = ReduceModel(model, tier);
    SpeedSweepOptions sweep_options;
    sweep_options.cycles = 256;
    sweep_options.transient_cycles = 100;
    sweep_options.waterfall_cycles = 255;
    sweep_options.threads = threads;
    const SpeedSweepResult sweep = RunSpeedSweep(
        spec, model, reduced, sweep_options,
        stage ? SweepProgress(counted("speed sweep", "speeds")) : SweepProgress());
    std::optional<AtlasResult> atlas;
    AtlasOptions atlas_options;
    if (o.atlas && spec.analysis.atlas_x && spec.analysis.atlas_y) {
      AtlasAxis x = *spec.analysis.atlas_x, y = *spec.analysis.atlas_y;
      x.range.points = std::min(x.range.points, 12);
      y.range.points = std::min(y.range.points, 12);
      atlas_options.tier = tier;
      atlas_options.transient_cycles = 270;
      atlas_options.cycles = 540;
      atlas_options.threads = threads;
      atlas = RunChaosAtlas(spec, x, y, atlas_options,
                            stage ? AtlasProgress(counted("chaos atlas", "cells")) : AtlasProgress());
    }
    long base_period = 1;
    try {
      base_period = BasePeriodCycles(op.tables);
    } catch (const InputError&) {
      base_period = 1;  // incommensurate orders: section every mesh cycle
    }

    // Images.
    if (stage) stage("images");
    render::ImageOptions image;
    image.width = o.width;
    image.height = o.height;
    image.dpi = o.dpi;
    render::ImageOptions small = image;
    small.width = std::max(200, o.width * 2 / 3);
    small.height = std::max(150, o.height * 2 / 3);
    std::vector<Figure> figures;
    auto draw = [&](const std::string& name, const std::string& caption,
                    const render::RenderStatus& status) {
      if (!status.ok) throw std::runtime_error("image " + name + ": " + status.message);
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
    draw("campbell.png",
         "Natural frequencies of the linearised tier (drive contact, mean mesh stiffness, "
         "gyroscopic terms) against speed; dashed: order lines; points: critical speeds.",
         render::RenderLinePlot(CampbellFigure(sweep), image, (folder / "campbell.png").string()));
    draw("waterfall.png", "Steady-state TE spectra across the speed sweep (pinion orders).",
         render::RenderHeatMap(WaterfallFigure(sweep), image, (folder / "waterfall.png").string()));
    draw("mesh_stiffness.png", "Mesh stiffness over one mesh cycle (potential energy method).",
         render::RenderLinePlot(MeshStiffnessFigure(model), small,
                                (folder / "mesh_stiffness.png").string()));
    draw("load_sharing.png", "Load sharing ratio of each tooth pair over one mesh cycle.",
         render::RenderLinePlot(LoadSharingFigure(model), small,
                                (folder / "load_sharing.png").string()));
    draw("lste.png", "Loaded static transmission error over one mesh cycle.",
         render::RenderLinePlot(LsteFigure(model), small, (folder / "lste.png").string()));
    if (atlas) {
      draw("atlas_lyapunov.png",
           "Largest Lyapunov exponent per forcing cycle (red: chaotic, blue: regular; strongly "
           "attracting cells are saturated at minus the largest positive value).",
           render::RenderHeatMap(AtlasFigure(*atlas, true, spec), image,
                                 (folder / "atlas_lyapunov.png").string()));
      draw("atlas_rattle.png", "Rattle index: impact energy per forcing cycle (log10 J).",
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
    WriteFileAtomically((folder / "waterfall.csv").string(), WaterfallCsv(sweep));
    if (atlas) WriteFileAtomically((folder / "atlas.csv").string(), AtlasCsv(*atlas, spec));
    std::vector<UffFunction> uff = OperatingPointUff(spec, op);
    for (UffFunction& f : SweepOrderTracksUff(spec, sweep, static_cast<int>(uff.size()) + 1)) {
      uff.push_back(std::move(f));
    }
    WriteFileAtomically((folder / "results.uff").string(), UffFile(uff));

    nlohmann::json results = {{"name", spec.name},
                              {"file", file},
                              {"check", check},
                              {"operating_point", op.doc},
                              {"base_period_mesh_cycles", base_period},
                              {"sweep", SweepJson(sweep, spec.pinion.teeth)}};
    if (atlas) results["atlas"] = AtlasJson(*atlas, atlas_options);
    nlohmann::json images = nlohmann::json::array();
    for (const Figure& f : figures) images.push_back({{"file", f.file}, {"caption", f.caption}});
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
      for (const AtlasCell& c : atlas->cells) chaotic += c.regime == "chaotic" ? 1 : 0;
    }
    entry.summary = {
        {"tier", op.tier_name},
        {"speed_rpm", spec.operating.speed * kRpm},
        {"torque_nm", spec.operating.torque},
        {"torque_on", TorqueOnName(spec.operating.torque_on)},
        {"speed", Format(spec.operating.speed, spec.operating.speed_unit)},
        {"torque", TorqueText(spec)},
        {"te_rms_um", op.te.rms * 1e6},
        {"te_peak_to_peak_um", op.te.peak_to_peak * 1e6},
        {"regime", r.regime},
        {"impacts_per_cycle", r.drive_impacts_per_cycle + r.back_impacts_per_cycle},
        {"acceleration_ratio", r.acceleration_ratio},
        {"first_critical_speed_rpm",
         std::isfinite(first_critical) ? nlohmann::json(first_critical) : nlohmann::json()},
        {"chaotic_atlas_cells", atlas ? nlohmann::json(chaotic) : nlohmann::json()},
        {"real_time_ratio", s.real_time_ratio}};

    // index.html
    std::ostringstream h;
    h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>"
      << Html(spec.name) << " - gearnvh report</title>\n"
      << kStyle << "\n</head><body>\n";
    h << "<h1>" << Html(spec.name) << "</h1>\n<p>" << Html(file) << " &middot; modal model "
      << Html(op.tier_name) << " &middot; <a href=\"results.json\">results.json</a> &middot; <a "
      << "href=\"../index.html\">batch</a></p>\n";
    for (const std::string& w : op.warnings) {
      h << "<p class=\"warning\">warning: " << Html(w) << "</p>\n";
    }
    const PairGeometry& g = model.geometry;
    h << "<h2>Gear pair and operating point</h2>\n<table>\n"
      << Row("teeth (pinion / wheel)", fmt::format("{} / {}", spec.pinion.teeth, spec.wheel.teeth))
      << Row("module (mm)", Number(spec.pinion.module * 1e3))
      << Row("contact ratio", Number(model.mesh_summary.contact_ratio))
      << Row("base radii (mm)",
             fmt::format("{} / {}", Number(g.pinion.base * 1e3), Number(g.wheel.base * 1e3)))
      << Row("mesh stiffness mean / min / max (N/µm)",
             fmt::format("{} / {} / {}", Number(model.mesh_summary.mean * 1e-6),
                         Number(model.mesh_summary.min * 1e-6),
                         Number(model.mesh_summary.max * 1e-6)))
      << Row("LSTE peak-to-peak (µm)", Number(model.mesh_summary.lste_peak_to_peak * 1e6))
      << Row("backlash (µm)", Number(spec.mesh.backlash * 1e6))
      << Row("pinion speed", Format(spec.operating.speed, spec.operating.speed_unit))
      << Row("mesh frequency (Hz)", Number(1.0 / op.tables.mesh_period))
      << Row("torque", TorqueText(spec)) << "</table>\n";
    const std::string factor_note = DynamicFactorNote(op.te);
    h << "<h2>Dynamics at the operating point</h2>\n<table>\n"
      << Row("dynamic TE RMS / peak-to-peak (µm)",
             fmt::format("{} / {}", Number(op.te.rms * 1e6), Number(op.te.peak_to_peak * 1e6)))
      << Row("dynamic TE mean (µm)",
             Number(op.te.mean * 1e6) + " (" + TeMeanNote(op.te, model.half_backlash) + ")")
      << Row("dynamic factor", Number(op.te.dynamic_factor) +
                                   (factor_note.empty() ? "" : " (" + factor_note + ")"))
      << Row("rattle regime", r.regime)
      << Row("impacts per mesh cycle (drive / back)",
             fmt::format("{} / {}", Number(r.drive_impacts_per_cycle),
                         Number(r.back_impacts_per_cycle)))
      << Row("impact velocity RMS (mm/s)", Number(r.impact_velocity_rms * 1e3))
      << Row("impact energy per mesh cycle (J)", Number(r.impact_energy_per_cycle))
      << Row("time separated (%)", Number(100.0 * r.separation_fraction))
      << Row("wheel acceleration RMS (rad/s²)", Number(r.wheel_acceleration_rms))
      << Row("acceleration ratio vs no backlash", Number(r.acceleration_ratio))
      << Row("solver real-time ratio", Number(s.real_time_ratio))
      << Row("mesh cycles simulated", std::to_string(s.mesh_cycles)) << "</table>\n";
    h << "<h2>Natural frequencies per modal tier (Hz)</h2>\n<table>\n<tr><th>tier</th><th>DOF"
         "</th><th>state</th><th>compliance error</th>";
    for (int k = 1; k <= 6; ++k) h << "<th>f" << k << "</th>";
    h << "</tr>\n<tr><td>full FE</td><td>" << model.dofs << "</td><td>-</td><td>-</td>";
    for (int k = 0; k < 6; ++k) {
      h << "<td>"
        << (k < static_cast<int>(modes.frequencies_hz.size()) ? Number(modes.frequencies_hz[k], 5)
                                                              : "-")
        << "</td>";
    }
    h << "</tr>\n";
    for (const ReducedModel& t : tiers) {
      h << "<tr><td>" << Html(t.name) << "</td><td>" << t.dof << "</td><td>" << StateDimension(model, t)
        << "</td><td>" << Number(100.0 * t.compliance_error_vs_full, 3) << " %</td>";
      for (int k = 0; k < 6; ++k) {
        h << "<td>"
          << (k < static_cast<int>(t.natural_frequencies_hz.size())
                  ? Number(t.natural_frequencies_hz[k], 5)
                  : "-")
          << "</td>";
      }
      h << "</tr>\n";
    }
    h << "</table>\n";
    h << "<h2>Critical speeds</h2>\n<table>\n<tr><th>order line</th><th>mode</th><th>speed "
         "(rpm)</th><th>frequency (Hz)</th></tr>\n";
    for (const CriticalSpeed& c : sweep.campbell.critical_speeds) {
      h << "<tr><td>" << Html(c.order) << "</td><td>" << c.mode + 1 << "</td><td>"
        << Number(c.speed_rpm, 5) << "</td><td>" << Number(c.frequency_hz, 5) << "</td></tr>\n";
    }
    if (sweep.campbell.critical_speeds.empty()) {
      h << "<tr><td colspan=\"4\">none in the sweep range</td></tr>\n";
    }
    h << "</table>\n<h2>Mesh harmonics and sidebands of the TE</h2>\n<table>\n<tr><th>line</th>"
         "<th>frequency (Hz)</th><th>amplitude (µm)</th><th>dB re 1 µm</th></tr>\n";
    for (const SidebandRow& row : op.sidebands) {
      h << "<tr><td>" << Html(row.label) << "</td><td>" << Number(row.frequency_hz, 6)
        << "</td><td>" << Number(row.amplitude * 1e6) << "</td><td>" << Number(row.db_re_1um, 4)
        << "</td></tr>\n";
    }
    if (op.sidebands.empty()) h << "<tr><td colspan=\"4\">too few recorded cycles</td></tr>\n";
    h << "</table>\n";
    if (atlas) {
      std::map<std::string, int> regimes;
      for (const AtlasCell& c : atlas->cells) ++regimes[c.ok ? c.regime : "failed"];
      h << "<h2>Chaos atlas</h2>\n<p>" << atlas->x.range.points << " x " << atlas->y.range.points
        << " cells (" << Html(atlas->x.parameter) << " x " << Html(atlas->y.parameter) << "), "
        << atlas_options.cycles << " mesh cycles each: ";
      for (const auto& [name, count] : regimes) h << Html(name) << " " << count << "; ";
      h << "<a href=\"atlas.csv\">atlas.csv</a></p>\n";
    }
    h << "<h2>Figures</h2>\n";
    for (const Figure& f : figures) {
      h << "<figure><img src=\"" << f.file << "\" alt=\"" << Html(f.caption) << "\"><figcaption>"
        << Html(f.caption) << "</figcaption></figure>\n";
    }
    h << "<h2>Data</h2>\n<p>";
    for (const char* csv : {"te_trace.csv", "spectrum.csv", "sidebands.csv", "mesh_cycle.csv",
                            "campbell.csv", "critical_speeds.csv", "waterfall.csv",
                            "results.uff"}) {
      h << "<a href=\"" << csv << "\">" << csv << "</a> ";
    }
    h << "</p>\n" << kImageCheckScript << "\n</body></html>\n";
    WriteFileAtomically((folder / "index.html").string(), h.str());
    entry.ok = true;
  } catch (const InputError& e) {
    entry.error = InputErrorMessage(e, file);
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

std::string BatchIndex(const std::vector<GearboxEntry>& entries) {
  std::ostringstream h;
  int failed = 0;
  for (const GearboxEntry& e : entries) failed += e.ok ? 0 : 1;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>gearnvh "
       "report</title>\n"
    << kStyle << "\n</head><body>\n<h1>gearnvh report</h1>\n<p>"
    << Count(static_cast<long>(entries.size()), "gearbox", "gearboxes") << ", "
    << (failed == 0 ? "<span class=\"ok\">all complete</span>"
                    : fmt::format("<span class=\"warn\">{} failed</span>", failed))
    << "</p>\n<table>\n<tr><th>gearbox</th><th>modal model</th><th>pinion speed</th><th>torque"
       "</th><th>TE RMS (µm)</th><th>rattle regime</th><th>impacts / mesh cycle</th><th>accel. "
       "ratio</th><th>first critical speed (rpm)</th><th>chaotic atlas cells</th><th>real-time "
       "ratio</th></tr>\n";
  for (const GearboxEntry& e : entries) {
    if (!e.ok) {
      h << "<tr><td>" << Html(e.file)
        << "</td><td colspan=\"10\" class=\"warn\">failed: " << Html(e.error);
      if (e.earlier_kept) {
        h << " (the result of an earlier run is kept: <a href=\"" << e.folder
          << "/index.html\">" << Html(e.folder) << "</a>)";
      }
      h << "</td></tr>\n";
      continue;
    }
    // An earlier run's summary may lack keys (older versions): a missing key reads as "-".
    const nlohmann::json& s = e.summary;
    auto text = [&s](const char* key) {
      const auto it = s.find(key);
      return it != s.end() && it->is_string() ? Html(it->get<std::string>()) : std::string("-");
    };
    auto num = [&s](const char* key) {
      const auto it = s.find(key);
      return it != s.end() && it->is_number() ? Number(it->get<double>()) : std::string("-");
    };
    h << "<tr><td><a href=\"" << e.folder << "/index.html\">" << Html(e.name) << "</a>"
      << (e.from_earlier ? " (earlier run)" : "") << "</td><td>" << text("tier") << "</td><td>"
      << text("speed") << "</td><td>" << text("torque") << "</td><td>" << num("te_rms_um")
      << "</td><td>" << text("regime") << "</td><td>" << num("impacts_per_cycle") << "</td><td>"
      << num("acceleration_ratio") << "</td><td>" << num("first_critical_speed_rpm")
      << "</td><td>" << num("chaotic_atlas_cells") << "</td><td>" << num("real_time_ratio")
      << "</td></tr>\n";
  }
  h << "</table>\n" << kImageCheckScript << "\n</body></html>\n";
  return h.str();
}

}  // namespace

namespace {

// A rank's finished gearboxes for rank 0: a JSON header (entries and file names) followed by the
// files' bytes, each preceded by its size (8 bytes).
void AppendSize(std::string& out, uint64_t n) { out.append(reinterpret_cast<const char*>(&n), 8); }
uint64_t ReadSize(const std::string& in, size_t& at) {
  uint64_t n = 0;
  std::memcpy(&n, in.data() + at, 8);
  at += 8;
  return n;
}

std::string PackEntries(const std::vector<size_t>& indices,
                        const std::vector<GearboxEntry>& entries, const fs::path& root) {
  nlohmann::json header = nlohmann::json::array();
  std::string blobs;
  for (size_t i : indices) {
    const GearboxEntry& e = entries[i];
    nlohmann::json files = nlohmann::json::array();
    if (e.ok) {
      for (const auto& f : fs::directory_iterator(root / e.folder)) {
        const std::string bytes = ReadWholeFileBytes(f.path());
        files.push_back(f.path().filename().string());
        AppendSize(blobs, bytes.size());
        blobs += bytes;
      }
    }
    header.push_back({{"index", i},
                      {"file", e.file},
                      {"folder", e.folder},
                      {"name", e.name},
                      {"ok", e.ok},
                      {"error", e.error},
                      {"summary", e.summary},
                      {"wall_s", e.wall_s},
                      {"files", files}});
  }
  const std::string text = header.dump();
  std::string out;
  AppendSize(out, text.size());
  out += text;
  out += blobs;
  return out;
}

void UnpackEntries(const std::string& packed, std::vector<GearboxEntry>& entries,
                   const fs::path& staging) {
  size_t at = 0;
  const uint64_t length = ReadSize(packed, at);
  const nlohmann::json header = nlohmann::json::parse(packed.substr(at, length));
  at += length;
  for (const auto& h : header) {
    GearboxEntry& e = entries[h.at("index").get<size_t>()];
    e.file = h.at("file").get<std::string>();
    e.folder = h.at("folder").get<std::string>();
    e.name = h.at("name").get<std::string>();
    e.ok = h.at("ok").get<bool>();
    e.error = h.at("error").get<std::string>();
    e.summary = h.at("summary");
    e.wall_s = h.at("wall_s").get<double>();
    if (!e.ok) continue;
    fs::create_directories(staging / e.folder);
    for (const auto& name : h.at("files")) {
      const uint64_t size = ReadSize(packed, at);
      WriteFileAtomically((staging / e.folder / name.get<std::string>()).string(),
                          packed.substr(at, size));
      at += size;
    }
  }
}

}  // namespace

namespace {

// The gearboxes of an earlier report in `dir` (its report.json), empty when there is none.
std::vector<GearboxEntry> EarlierEntries(const fs::path& dir) {
  std::vector<GearboxEntry> out;
  if (!fs::exists(dir / kMarker) || !fs::exists(dir / "report.json")) return out;
  try {
    const nlohmann::json doc = nlohmann::json::parse(ReadWholeFileBytes(dir / "report.json"));
    for (const auto& g : doc.at("gearboxes")) {
      GearboxEntry e;
      e.file = g.at("file").get<std::string>();
      e.folder = g.at("folder").get<std::string>();
      e.name = g.at("name").get<std::string>();
      e.ok = g.at("ok").get<bool>();
      e.summary = g.at("summary");
      e.wall_s = g.at("wall_s").get<double>();
      if (e.ok && !e.folder.empty() && fs::is_directory(dir / e.folder)) out.push_back(e);
    }
  } catch (const std::exception&) {
    // An unreadable earlier index: its gearbox folders stay, unlisted.
  }
  return out;
}

}  // namespace

int RunReport(const ReportCommandOptions& o) {
  const int rank = MpiContext::Rank(), ranks = MpiContext::Size();
  int code = 0;
  try {
    if (o.files.empty()) throw InputError("FILE", 0, "(none)", "give at least one gearbox file");
    const render::ImageOptions image{o.width, o.height, o.dpi};
    try {
      image.Validate();
    } catch (const std::invalid_argument& e) {
      throw InputError("--width/--height/--dpi", 0, "", e.what());
    }
    const fs::path out = fs::absolute(o.out).lexically_normal();
    if (fs::exists(out) && fs::is_directory(out) && !fs::is_empty(out) &&
        !fs::exists(out / kMarker)) {
      throw IoError("--out " + o.out +
                    ": exists and is not a gearnvh report; refusing to mix results into it "
                    "(choose a new folder or an earlier report's folder)");
    }
    // Checked, locked and staged before any work (every rank learns rank 0's verdict).
    const std::unique_ptr<OutputFolder> target = OpenOutputFolder(o.out, "--out", true);
    // Images need a display: fail before any work when rank 0 has none (every rank starts its own
    // Xvfb when DISPLAY is unset; a rank without one reports its gearboxes as failed).
    const render::DisplayStatus& display = render::EnsureDisplay();
    if (MpiContext::BroadcastInt(display.ok() ? 1 : 0) == 0) {
      std::cerr << "error: " << display.message << "\n";
      return 1;
    }
    const std::string suffix = std::to_string(static_cast<long>(::getpid()));
    // Rank 0 builds the report in the output folder's staging folder; other ranks in a private
    // scratch folder whose files they send to rank 0.
    const fs::path scratch = fs::temp_directory_path() /
                             ("gearnvh-report-rank" + std::to_string(rank) + "-" + suffix);
    const fs::path staging = rank == 0 ? target->staging() : scratch;
    if (rank != 0) {
      fs::remove_all(scratch);
      fs::create_directories(scratch);
      RemoveOnSignal(scratch);
    }
    std::vector<std::string> folders;
    std::set<std::string> used;
    for (const std::string& f : o.files) {
      std::string name = Slug(f);
      for (int k = 2; used.count(name) != 0; ++k) name = Slug(f) + "-" + std::to_string(k);
      used.insert(name);
      folders.push_back(name);
    }
    std::vector<size_t> mine;
    for (size_t i = 0; i < o.files.size(); ++i) {
      if (static_cast<int>(i % static_cast<size_t>(ranks)) == rank) mine.push_back(i);
    }
    const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    const int jobs =
        std::max(1, std::min<int>(o.jobs > 0 ? o.jobs : hardware, static_cast<int>(mine.size())));
    const int inner = std::max(1, hardware / jobs);
    std::vector<GearboxEntry> entries(o.files.size());
    std::atomic<size_t> next{0};
    std::mutex progress_mutex;
    size_t done = 0;
    const bool on_terminal = rank == 0 && ::isatty(STDERR_FILENO) != 0;
    // One gearbox: its stages and cycles on the terminal (a batch shows the gearboxes done).
    StageProgress stage;
    if (on_terminal && mine.size() == 1) {
      stage = [&progress_mutex, file = o.files[mine.front()]](const std::string& what) {
        const std::lock_guard<std::mutex> lock(progress_mutex);
        fmt::print(stderr, "\rreport: {}: {}\x1b[K", file, what);
      };
    }
    auto worker = [&]() {
      for (size_t k = next++; k < mine.size(); k = next++) {
        const size_t i = mine[k];
        if (display.ok()) {
          entries[i] = BuildGearboxReport(o.files[i], staging / folders[i], o, inner, stage);
        } else {
          entries[i].file = o.files[i];
          entries[i].folder = folders[i];
          entries[i].error = display.message;
        }
        const std::lock_guard<std::mutex> lock(progress_mutex);
        ++done;
        if (on_terminal && !stage) {
          fmt::print(stderr, "\rreport: {} of {}{}", done,
                     Count(static_cast<long>(mine.size()), "gearbox", "gearboxes"),
                     ranks > 1 ? fmt::format(" on rank 0 of {}", ranks) : "");
        }
      }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < jobs; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (on_terminal) fmt::print(stderr, "\n");
    if (ranks > 1) {
      const std::vector<std::string> parts =
          MpiContext::GatherToRoot(rank == 0 ? std::string() : PackEntries(mine, entries, staging));
      if (rank != 0) {
        fs::remove_all(scratch);
        ForgetOnSignal(scratch);
        return MpiContext::BroadcastInt(0);
      }
      for (size_t r = 1; r < parts.size(); ++r) UnpackEntries(parts[r], entries, staging);
    }

    int failed = 0, internal = 0;
    for (const GearboxEntry& e : entries) {
      failed += e.ok ? 0 : 1;
      internal += e.internal ? 1 : 0;
      if (!e.ok) fs::remove_all(staging / e.folder);
    }
    for (const GearboxEntry& e : entries) {
      if (!e.ok) std::cerr << "error: " << e.error << "\n";
    }
    if (failed == static_cast<int>(entries.size())) {
      // Nothing new to show: DIR (an earlier report, or nothing) stays exactly as it was.
      std::cerr << "error: all " << entries.size() << " gearboxes failed; "
                << (fs::exists(out) ? out.string() + " is unchanged" : "nothing was written")
                << "\n";
      return MpiContext::BroadcastInt(internal > 0 ? kExitInternal : kExitInput);
    }
    // The batch index covers this run and keeps what an earlier report in DIR showed: a gearbox
    // that failed now keeps its earlier folder, earlier gearboxes not in this run stay listed.
    std::vector<GearboxEntry> listed = entries;
    std::set<std::string> this_run(folders.begin(), folders.end());
    for (GearboxEntry e : EarlierEntries(out)) {
      if (this_run.count(e.folder) == 0) {
        e.from_earlier = true;
        listed.push_back(e);
        continue;
      }
      for (GearboxEntry& now : listed) {
        if (!now.ok && now.folder == e.folder) now.earlier_kept = true;
      }
    }
    nlohmann::json batch = nlohmann::json::array();
    for (const GearboxEntry& e : listed) {
      batch.push_back({{"file", e.file},
                       {"folder", e.ok || e.earlier_kept ? e.folder : ""},
                       {"name", e.name},
                       {"ok", e.ok},
                       {"error", e.error},
                       {"earlier_result_kept", e.earlier_kept},
                       {"from_earlier_run", e.from_earlier},
                       {"summary", e.summary},
                       {"wall_s", e.wall_s}});
    }
    target->Write("index.html", BatchIndex(listed));
    target->Write("report.json", nlohmann::json{{"gearboxes", batch},
                                                {"failed", failed},
                                                {"ranks", ranks}}
                                         .dump(1) +
                                     "\n");
    target->Write(kMarker, "gearnvh report\n");
    // Each gearbox folder and the index replace their earlier versions one by one, atomically.
    target->Commit();
    for (const GearboxEntry& e : entries) {
      if (e.ok) {
        fmt::print("{}: {} -> {}/index.html ({:.1f} s)\n", e.file, e.name,
                   (out / e.folder).string(), e.wall_s);
      }
    }
    fmt::print("report: {}\n", (out / "index.html").string());
    if (failed > 0) {
      std::cerr << "error: " << failed << " of "
                << Count(static_cast<long>(entries.size()), "gearbox", "gearboxes")
                << " failed (listed in the batch index)\n";
      code = internal > 0 ? kExitInternal : kExitInput;
    }
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return ExitCodeOf(e);  // every rank sees the same input and the same error
  } catch (const IoError& e) {
    std::cerr << "error: " << e.what() << "\n";
    code = kExitIo;
  } catch (const fs::filesystem_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    code = kExitIo;
  }
  return MpiContext::BroadcastInt(code);
}

}  // namespace gearnvh::app
