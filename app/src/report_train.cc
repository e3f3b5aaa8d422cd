#include "report_train.h"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

#include "atomic_file.h"
#include "display_units.h"
#include "finite_results.h"
#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/analysis/train_atlas.h"
#include "gearnvh/analysis/train_operating_point.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/solver/train_reduced_tables.h"
#include "report_figures.h"
#include "report_html.h"
#include "report_sweep_figures.h"
#include "report_whine.h"
#include "result_documents.h"
#include "train_check.h"
#include "train_command_options.h"
#include "train_sweep_command.h"
#include "uff_export.h"

namespace gearnvh::app {

namespace fs = std::filesystem;

namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;  // degrees per radian

// One series per mesh (or loose gear) of `value` against the input speed; failed speeds left out.
template <typename Value>
render::LinePlot OverSpeed(const TrainSweepResult& sweep, const std::vector<std::string>& names,
                           const std::string& title, const std::string& y_label, Value value,
                           AxisScale speed_scale) {
  render::LinePlot p;
  p.title = title;
  p.x_label = "input speed (rpm)";
  p.y_label = y_label;
  p.log_x = speed_scale == AxisScale::kLog;
  for (size_t i = 0; i < names.size(); ++i) {
    render::Series s{names[i], {}, {}};
    for (const TrainSweepPoint& point : sweep.points) {
      if (!point.ok) continue;
      s.x.push_back(point.speed_rpm);
      s.y.push_back(value(point, i));
    }
    p.series.push_back(std::move(s));
  }
  return p;
}

std::string TrainSidebandsCsv(const TrainOperatingPoint& op) {
  std::ostringstream os;
  os.precision(12);
  os << "mesh,label,frequency_hz,amplitude_m,db_re_1um\n";
  for (size_t i = 0; i < op.sidebands.size(); ++i) {
    for (const SidebandRow& r : op.sidebands[i].rows) {
      os << op.tables.meshes[i].name << ',' << r.label << ',' << r.frequency_hz << ','
         << r.amplitude << ',' << r.db_re_1um << '\n';
    }
  }
  return os.str();
}

// Each coupling's twist and torque over the record (exact: closed-form integrals and certified
// extrema), in degrees and N m; nothing without a coupling.
std::string CouplingsHtml(const TrainOperatingPoint& op) {
  if (op.couplings.empty()) return {};
  std::ostringstream h;
  h << "<h2>Couplings at the operating point</h2>\n<p>Twist of the first shaft over the second "
       "in their direction of rotation and the torque passed on (k twist + c twist' and every "
       "engaged stage of a multi-stage coupling), exact over "
       "the record (couplings.png: the twist over time).</p>\n<table>\n<tr><th>coupling</th>"
       "<th>twist mean / RMS about it (deg)</th><th>twist min / max (deg)</th><th>torque mean / "
       "RMS about it (N m)</th><th>torque min / max (N m)</th></tr>\n";
  for (const TrainCouplingResponse& c : op.couplings) {
    h << "<tr><td>" << Html(c.name) << "</td><td>"
      << fmt::format("{} / {}", Number(c.twist.mean * kDeg), Number(c.twist.rms * kDeg))
      << "</td><td>"
      << fmt::format("{} / {}", Number(c.twist.min * kDeg), Number(c.twist.max * kDeg))
      << "</td><td>" << fmt::format("{} / {}", Number(c.torque.mean), Number(c.torque.rms))
      << "</td><td>" << fmt::format("{} / {}", Number(c.torque.min), Number(c.torque.max))
      << "</td></tr>\n";
  }
  h << "</table>\n";
  return h.str();
}

struct TrainPageInput {
  const std::string& file;
  const TrainSpec& spec;
  const TrainCheck& check;
  const TrainOperatingPoint& op;
  const TrainSweepResult& sweep;
  const std::vector<std::pair<std::string, std::string>>& figures;  // file, caption
  const std::string& whine_html;  // the whine section (report_whine.h)
};

std::string TrainPage(const TrainPageInput& in) {
  const TrainOperatingPoint& op = in.op;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>"
    << Html(in.spec.name) << " - gearnvh report</title>\n"
    << kReportStyle << "\n</head><body>\n";
  h << "<h1>" << Html(in.spec.name) << "</h1>\n<p>" << Html(in.file) << " &middot; gear train, "
    << TierName(op.tier)
    << " &middot; <a href=\"results.json\">results.json</a> &middot; "
       "<a href=\"../index.html\">batch</a></p>\n";
  for (const std::string& w : op.warnings) {
    h << "<p class=\"warning\">warning: " << Html(w) << "</p>\n";
  }
  h << "<h2>Operating point</h2>\n<table>\n"
    << Row("input shaft", in.spec.operating.input_shaft)
    << Row("input speed (rpm)", Number(Rpm(in.spec.operating.speed)))
    << Row("bodies / meshes", fmt::format("{} / {}", op.tables.bodies(), op.tables.gear_meshes))
    << Row("common period (s)", op.tables.common_period > 0.0
                                    ? Number(op.tables.common_period)
                                    : std::string("none within 1000 input revolutions"))
    << Row("simulated / recorded (s)", fmt::format("{} / {}", Number(op.summary.simulated_time),
                                                   Number(op.stats.recorded_time)))
    << Row("contact events", std::to_string(op.summary.events))
    << Row("real-time ratio", Number(op.wall_s > 0.0 ? op.summary.simulated_time / op.wall_s : 0.0))
    << "</table>\n";
  h << "<h2>Meshes at the operating point</h2>\n<p>TE, force and rattle index exact (closed-form "
       "integrals and certified extrema of the recorded trajectory), impacts and separation from "
       "the exact events (docs/results.md, \"Gear "
       "trains\"); the TE mean includes the half backlash b.</p>\n<table>\n<tr><th>mesh</th>"
       "<th>mesh frequency (Hz)</th><th>b (µm)</th><th>TE mean / RMS / p-p (µm)</th><th>mesh "
       "force mean / max (N)</th><th>impacts / mesh cycle (drive / back)</th><th>separated</th>"
       "</tr>\n";
  for (size_t i = 0; i < op.stats.meshes.size(); ++i) {
    const TrainMeshStatistics& m = op.stats.meshes[i];
    const TrainMeshTable& mt = op.tables.meshes[i];
    const double cycles = op.stats.recorded_time / mt.period;
    h << "<tr><td>" << Html(m.name) << "</td><td>" << Number(1.0 / mt.period) << "</td><td>"
      << Number(mt.half_backlash * 1e6) << "</td><td>"
      << fmt::format("{} / {} / {}", Number(m.te_mean * 1e6), Number(m.te_rms * 1e6),
                     Number(m.te_peak_to_peak * 1e6))
      << "</td><td>" << fmt::format("{} / {}", Number(m.force_mean), Number(m.force_max))
      << "</td><td>"
      << fmt::format("{} / {}", Number(cycles > 0 ? m.drive_impacts / cycles : 0.0),
                     Number(cycles > 0 ? m.back_impacts / cycles : 0.0))
      << "</td><td>" << Number(100.0 * m.free_time_fraction, 3) << " %</td></tr>\n";
  }
  h << "</table>\n";
  h << "<h2>Loose gears by impact energy</h2>\n";
  if (op.stats.loose_gears.empty()) {
    h << "<p>The train has no loose gear.</p>\n";
  } else {
    h << "<p>Ranked by impact energy per second, ½ m<sub>e</sub> v² summed over the impacts of "
         "the gear's meshes (v the gap's closing speed); a gear without an impact does not "
         "rattle (rank –). The RMS angular acceleration is shown beside it.</p>\n"
         "<table>\n<tr><th>rank</th><th>loose gear</th><th>impact energy (mW)</th><th>drive "
         "impacts / s</th><th>back impacts / s</th><th>impact velocity RMS (mm/s)</th><th>impact "
         "velocity max (mm/s)</th><th>RMS angular acceleration (rad/s²)</th></tr>\n";
    for (const TrainLooseGearStatistics& g : op.stats.loose_gears) {
      h << "<tr><td>" << (g.rank > 0 ? std::to_string(g.rank) : "–") << "</td><td>"
        << Html(g.name) << "</td><td>" << Number(g.impact_energy_per_second * 1e3) << "</td><td>"
        << Number(g.drive_impacts_per_second) << "</td><td>" << Number(g.back_impacts_per_second)
        << "</td><td>" << Number(g.impact_velocity_rms * 1e3) << "</td><td>"
        << Number(g.impact_velocity_max * 1e3) << "</td><td>" << Number(g.rattle_index)
        << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  h << CouplingsHtml(op);
  h << "<h2>TE spectrum lines per mesh</h2>\n<table>\n<tr><th>mesh</th><th>line</th><th>frequency "
       "(Hz)</th><th>amplitude (µm)</th><th>dB re 1 µm</th></tr>\n";
  for (size_t i = 0; i < op.sidebands.size(); ++i) {
    for (const SidebandRow& r : op.sidebands[i].rows) {
      h << "<tr><td>" << Html(op.tables.meshes[i].name) << "</td><td>" << Html(r.label)
        << "</td><td>" << Number(r.frequency_hz) << "</td><td>" << Number(r.amplitude * 1e6)
        << "</td><td>" << Number(r.db_re_1um) << "</td></tr>\n";
    }
  }
  h << "</table>\n";
  for (const std::string& note : op.sideband_notes) h << "<p>" << Html(note) << "</p>\n";
  const CampbellData& c = in.check.campbell;
  h << "<h2>Critical speeds (" << Html(TierName(in.check.campbell_tier))
    << ", inside the speed sweep)</h2>\n";
  if (c.critical_speeds.empty()) {
    h << "<p>No order line crosses a tracked mode inside the sweep.</p>\n";
  } else {
    h << "<table>\n<tr><th>input speed (rpm)</th><th>order line</th><th>mode</th><th>frequency "
         "(Hz)</th></tr>\n";
    for (const CriticalSpeed& s : c.critical_speeds) {
      h << "<tr><td>" << Number(s.speed_rpm) << "</td><td>" << Html(s.order) << "</td><td>"
        << s.mode + 1 << " (" << Html(c.modes[static_cast<size_t>(s.mode)].Label()) << ")</td><td>"
        << Number(s.frequency_hz) << "</td></tr>\n";
    }
    h << "</table>\n";
  }
  h << "<h2>Speed sweep</h2>\n<p>" << SweepSpeedsHtml(in.sweep.points, "input speeds")
    << ". Per speed and mesh: meshes.csv; per speed and loose gear: loose_gears.csv.</p>\n";
  h << in.whine_html;
  h << "<h2>Figures</h2>\n";
  for (const auto& [name, caption] : in.figures) {
    h << "<figure><img src=\"" << name << "\" alt=\"" << Html(caption) << "\"><figcaption>"
      << Html(caption) << "</figcaption></figure>\n";
  }
  h << "<p>Data: <a href=\"meshes.csv\">meshes.csv</a>, <a href=\"loose_gears.csv\">"
       "loose_gears.csv</a>, <a href=\"sidebands.csv\">sidebands.csv</a>, <a "
       "href=\"waterfall.csv\">waterfall.csv</a>, <a href=\"order_tracks.csv\">order_tracks.csv"
       "</a>, <a href=\"results.uff\">results.uff</a> (UFF dataset 58: every mesh's TE and force "
       "histories, TE spectrum and order tracks), <a href=\"results.json\">results.json</a>. Not "
       "built for trains yet: the chaos atlas and tier comparison of a gear pair's report.</p>\n";
  h << kImageCheckScript << "\n</body></html>\n";
  return h.str();
}

// What the batch index lists for a train (report_batch.h): the pair's keys where they have a
// meaning for a train, TE RMS and impacts per cycle per mesh, and the loudest loose gear.
nlohmann::json TrainSummary(const TrainSpec& spec, const TrainCheck& check,
                            const TrainOperatingPoint& op) {
  double first_critical = std::numeric_limits<double>::quiet_NaN();
  for (const CriticalSpeed& c : check.campbell.critical_speeds) {
    if (!std::isfinite(first_critical) || c.speed_rpm < first_critical)
      first_critical = c.speed_rpm;
  }
  nlohmann::json meshes = nlohmann::json::array();
  for (size_t i = 0; i < op.stats.meshes.size(); ++i) {
    const TrainMeshStatistics& m = op.stats.meshes[i];
    const double cycles = op.stats.recorded_time / op.tables.meshes[i].period;
    meshes.push_back(
        {{"name", m.name},
         {"te_rms_um", m.te_rms * 1e6},
         {"impacts_per_cycle",
          cycles > 0.0 ? static_cast<double>(m.drive_impacts + m.back_impacts) / cycles : 0.0}});
  }
  const std::vector<TrainLooseGearStatistics>& loose = op.stats.loose_gears;
  // The gear ranked first, if any gear impacts (the list puts impacting gears first).
  const TrainLooseGearStatistics* loudest =
      !loose.empty() && loose.front().rank == 1 ? &loose.front() : nullptr;
  return {
      {"tier", std::string(TierName(op.tier)) + " (gear train)"},
      {"speed", Format(spec.operating.speed, spec.operating.speed_unit) + " (" +
                    spec.operating.input_shaft + ")"},
      {"speed_rpm", Rpm(spec.operating.speed)},
      {"torque", TrainLoadsText(spec)},
      {"meshes", meshes},
      {"loose_gears", loose.size()},
      {"loudest_loose_gear", loudest ? nlohmann::json(loudest->name) : nlohmann::json()},
      {"loudest_loose_gear_impact_energy_per_second_w",
       loudest ? nlohmann::json(loudest->impact_energy_per_second) : nlohmann::json()},
      {"first_critical_speed_rpm",
       std::isfinite(first_critical) ? nlohmann::json(first_critical) : nlohmann::json()},
      {"real_time_ratio", op.wall_s > 0.0 ? op.summary.simulated_time / op.wall_s : 0.0}};
}

}  // namespace

nlohmann::json BuildTrainReport(const std::string& file, const fs::path& folder,
                                const ReportCommandOptions& o, int threads,
                                const StageProgress& stage, const TrainSpec& spec,
                                const std::optional<MemoryLimit>& memory) {
  // analysis.tier must be a tier the train has (tiers 4, 5 and N20 need an elastic shaft).
  const TrainCommandSettings settings =
      CheckTrainCommandOptions(std::nullopt, spec, LadderMethod::kV3);
  if (stage) stage("train model, modes and Campbell data");
  const TrainCheck check = BuildTrainCheck(spec);
  TrainRunOptions run;
  run.tier = settings.tier;
  run.cycles = spec.analysis.cycles;
  run.transient = spec.analysis.transient_cycles;
  run.histories = true;  // results.uff
  run.tier_adequacy = true;
  run.before_run_memory = [&](RunMemory& need) {
    MemoryPart uff = OperatingPointUffMemory(need.recorded_samples);  // results.uff
    uff.bytes *= spec.meshes.size() + spec.couplings.size();  // a coupling's twist and torque
    need.parts.push_back(uff);
    return CheckRunMemory(need, memory, "analysis.cycles", std::to_string(run.cycles));
  };
  TrainSweepOptions sweep_options;
  sweep_options.cycles = 256;
  sweep_options.transient = 100;
  sweep_options.threads = threads;
  sweep_options.tier = settings.tier;
  // The operating point's and the sweep's cost, said (or refused) before either runs; the
  // operating point then runs on the tables estimated.
  GearTrain train = check.train;
  TrainTables tables = BuildTrainTablesAtTier(spec, train, settings.tier);
  const double seconds =
      static_cast<double>(run.cycles + run.transient) * tables.meshes.front().period;
  const RunCostEstimate cost = CombineRunCosts(
      {EstimateRunCost(tables, seconds, &spec), EstimateTrainSweepCost(spec, sweep_options)}, 1);
  const std::string slow = CheckRunCost(cost, o.allow_slow, "the operating point and the sweep");
  if (!slow.empty()) fmt::print(stderr, "warning: {}: {}\n", file, slow);
  run.allow_slow = sweep_options.allow_slow = true;
  if (stage) stage("operating point");
  const TrainOperatingPoint op =
      RunTrainOperatingPoint(spec, std::move(train), std::move(tables), run);
  if (!op.ok()) {
    throw std::runtime_error("operating point: " + TrainStepperMessage(op.summary));
  }
  const TrainSweepResult sweep =
      RunTrainSweep(spec, sweep_options,
                    stage ? TrainSweepProgress([&stage](int done, int total) {
                      stage(fmt::format("speed sweep {}/{} speeds", done, total));
                    })
                          : TrainSweepProgress());

  if (stage) stage("images");
  render::ImageOptions image;
  image.width = o.width;
  image.height = o.height;
  image.dpi = o.dpi;
  std::vector<std::pair<std::string, std::string>> figures;
  auto draw = [&](const std::string& name, const std::string& caption,
                  const render::RenderStatus& status) {
    ThrowUnlessDrawn(name, status);
    figures.emplace_back(name, caption);
  };
  const AxisScale scale = spec.analysis.speed_sweep.scale;
  std::vector<double> campbell_rpm;
  for (double w : check.campbell.speeds_rad_s) campbell_rpm.push_back(Rpm(w));
  draw("campbell.png",
       std::string("Every tracked natural frequency of the train's ") +
           TierName(check.campbell_tier) +
           " (every mesh in drive contact at its mean stiffness, gyroscopic terms) against the "
           "input speed; dashed: order lines of every shaft and mesh; points: critical speeds.",
       render::RenderLinePlot(
           CampbellFigure(check.campbell, campbell_rpm, scale, "input speed (rpm)"), image,
           (folder / "campbell.png").string()));
  draw("mesh_impacts.png",
       "Rattle index per mesh: impacts (drive + back) per cycle of that mesh against the input "
       "speed (exact events; meshes.csv).",
       render::RenderLinePlot(
           OverSpeed(
               sweep, sweep.mesh_names, "Impacts per mesh cycle", "impacts per mesh cycle (-)",
               [](const TrainSweepPoint& p, size_t i) { return p.ImpactsPerCycle(i); }, scale),
           image, (folder / "mesh_impacts.png").string()));
  draw("mesh_te.png", "Dynamic TE RMS per mesh against the input speed (exact; meshes.csv).",
       render::RenderLinePlot(
           OverSpeed(
               sweep, sweep.mesh_names, "Dynamic TE RMS per mesh", "TE RMS (µm)",
               [](const TrainSweepPoint& p, size_t i) { return p.meshes[i].te_rms * 1e6; }, scale),
           image, (folder / "mesh_te.png").string()));
  // Every mesh's 1x mesh-order track solid, its 2x dashed in the same colour; a waterfall each.
  std::vector<OrderTrack> first_orders, second_orders, every_order;
  for (size_t i = 0; i < sweep.mesh_names.size(); ++i) {
    const std::vector<OrderTrack> tracks =
        MeshOrderTracks(MeshWaterfall(sweep, i), sweep.mesh_orders[i], 3, sweep.mesh_names[i]);
    first_orders.push_back(tracks[0]);
    second_orders.push_back(tracks[1]);
    every_order.insert(every_order.end(), tracks.begin(), tracks.end());
  }
  draw("order_tracks.png",
       "TE amplitude at each mesh's own mesh order (solid) and twice it (dashed, same colour) "
       "against the input speed: the mesh-order resonances (order_tracks.csv holds orders 1-3).",
       render::RenderLinePlot(
           OrderTrackFigure(first_orders, second_orders, scale,
                            "Order tracks: TE at each mesh's 1x and 2x mesh order", "input",
                            DashedColours::kAsSolid),
           image, (folder / "order_tracks.png").string()));
  for (size_t i = 0; i < sweep.mesh_names.size(); ++i) {
    const std::string name = fmt::format("waterfall_{}.png", i + 1);
    draw(name,
         fmt::format("Waterfall of mesh {} (mesh order {} of the input shaft): its TE amplitude "
                     "over input orders and speed (waterfall.csv).",
                     sweep.mesh_names[i], Number(sweep.mesh_orders[i])),
         render::RenderHeatMap(
             WaterfallFigure(MeshWaterfall(sweep, i), sweep.order_bins, scale, "input",
                             "Waterfall: TE of mesh " + sweep.mesh_names[i]),
             image, (folder / name).string()));
  }
  if (stage) stage("whine");
  const WhineReport whine = BuildWhineReport(spec, settings.tier, threads, folder, image);
  for (const ReportFigure& f : whine.figures) figures.emplace_back(f.file, f.caption);
  std::vector<std::pair<std::string, FaceLoad>> faces;
  for (const TrainMeshModel& m : check.train.meshes) {
    if (m.cycle.face.modelled()) faces.emplace_back(m.name, m.cycle.face);
  }
  if (!faces.empty()) {
    draw("face_load.png",
         "Load per unit face width across each misaligned or lead-modified mesh's face (K_Hβ: "
         "its peak over the mean; `check` gives the misalignment components).",
         render::RenderLinePlot(FaceLoadFigure(faces), image, (folder / "face_load.png").string()));
  }
  if (!op.histories.coupling_twist.empty()) {
    // Ten input revolutions: the engine orders' cycles stay apart, and a slow shuffle shows.
    const double window_s = std::min(10.0 * op.tables.InputRevolution(), op.stats.recorded_time);
    draw("couplings.png",
         fmt::format("Twist of each coupling (the clutch damper's relative angle) over the last "
                     "{} s (ten input revolutions, or the whole record if shorter) of the "
                     "operating point, exact at every sample; "
                     "dashed: its exact mean over the record (the static twist T / k plus the "
                     "motion's mean). The table above holds the whole record's extrema.{}",
                     Number(window_s, 3),
                     op.histories.truncated
                         ? " The record held more samples than are kept: the figure ends where "
                           "the kept samples do."
                         : ""),
         render::RenderLinePlot(CouplingTwistFigure(op, window_s), image,
                                (folder / "couplings.png").string()));
  }
  if (!spec.couplings.empty()) {
    // Each coupling's twist range (its exact minimum and maximum) at every sweep speed.
    std::vector<std::string> ranges;
    for (const TrainCoupling& c : spec.couplings) {
      ranges.push_back(c.name + " max");
      ranges.push_back(c.name + " min");
    }
    render::LinePlot range = OverSpeed(
        sweep, ranges, "Coupling twist range", "twist (deg)",
        [](const TrainSweepPoint& p, size_t i) {
          const TrainOutputSummary& t = p.couplings[i / 2].twist;
          return (i % 2 == 0 ? t.max : t.min) * kDeg;
        },
        scale);
    range.auto_log_y = false;
    for (size_t i = 0; i < range.series.size(); ++i) {  // a coupling's minimum dashed in its colour
      range.series[i].color = static_cast<int>(i / 2);
      if (i % 2 == 1) range.series[i].style = render::Series::Style::kDashed;
    }
    draw("couplings_over_speed.png",
         "Twist range of each coupling against the input speed: its exact maximum (solid) and "
         "minimum (dashed) over each speed's record (couplings.csv): where a clutch damper "
         "leaves the stage its stiffness was given for.",
         render::RenderLinePlot(range, image, (folder / "couplings_over_speed.png").string()));
  }
  if (!sweep.loose_gear_names.empty()) {
    draw(
        "loose_gears.png",
        "Impact energy per second of each loose gear against the input speed; 0 where it does "
        "not impact (loose_gears.csv, with the impact rates, velocities and RMS acceleration).",
        render::RenderLinePlot(
            OverSpeed(
                sweep, sweep.loose_gear_names, "Loose gears: impact energy", "impact energy (mW)",
                [&sweep](const TrainSweepPoint& p, size_t i) {
                  const TrainLooseGearStatistics* g =
                      FindLooseGear(p.loose_gears, sweep.loose_gear_names[i]);
                  return g ? g->impact_energy_per_second * 1e3 : 0.0;
                },
                scale),
            image, (folder / "loose_gears.png").string()));
  }

  if (stage) stage("data files and page");
  WriteFileAtomically((folder / "meshes.csv").string(), TrainMeshesCsv(sweep));
  WriteFileAtomically((folder / "loose_gears.csv").string(), TrainLooseGearsCsv(sweep));
  if (!spec.couplings.empty())
    WriteFileAtomically((folder / "couplings.csv").string(), TrainCouplingsCsv(sweep));
  WriteFileAtomically((folder / "sidebands.csv").string(), TrainSidebandsCsv(op));
  WriteFileAtomically((folder / "waterfall.csv").string(),
                      WaterfallCsv(MeshWaterfalls(sweep), sweep.mesh_names));
  WriteFileAtomically((folder / "order_tracks.csv").string(),
                      OrderTracksCsv(every_order, {}, "input"));
  {
    std::vector<UffFunction> uff = TrainOperatingPointUff(spec, op);
    for (UffFunction& f : TrainSweepOrderTracksUff(spec, sweep, static_cast<int>(uff.size()) + 1))
      uff.push_back(std::move(f));
    WriteUffFile((folder / "results.uff").string(), uff);
  }
  nlohmann::json images = nlohmann::json::array();
  for (const auto& [name, caption] : figures)
    images.push_back({{"file", name}, {"caption", caption}});
  const nlohmann::json adequacy =
      op.adequacy_options ? TierAdequacyJson(op.adequacy, *op.adequacy_options, MeshNames(spec))
                          : nlohmann::json(nullptr);
  nlohmann::json results = {
      {"name", spec.name},
      {"file", file},
      {"schema", "gearnvh/2"},
      {"check", TrainCheckReport(spec, check)},
      {"operating_point",
       {{"meshes", TrainMeshesJson(op)},
        {"loose_gears", TrainLooseGearsJson(op.stats.loose_gears)},
        {"couplings", TrainCouplingsJson(op.couplings, op.stats.recorded_time)},
        {"sideband_window_common_periods", op.sideband_window_common_periods},
        {"sidebands_notes", op.sideband_notes},
        {"warnings", op.warnings},
        {"tier_adequacy", adequacy}}},
      {"sweep", TrainSweepJson(sweep)},
      {"whine", whine.summary},
      {"images", images}};
  RequireFinite(results, "results.json");
  WriteFileAtomically((folder / "results.json").string(), results.dump(1) + "\n");
  WriteFileAtomically((folder / "index.html").string(),
                      TrainPage({file, spec, check, op, sweep, figures, whine.html}));

  nlohmann::json summary = TrainSummary(spec, check, op);
  summary["failed_speeds"] = sweep.failed();
  return summary;
}

}  // namespace gearnvh::app
