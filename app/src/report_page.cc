#include "report_page.h"

#include <fmt/format.h>

#include <map>
#include <sstream>

#include "check_command.h"
#include "display_units.h"
#include "report_html.h"
#include "result_documents.h"

namespace gearnvh::app {

std::string GearboxPage(const GearboxPageInput& in) {
  const GearboxSpec& spec = in.spec;
  const ComponentModel& model = in.model;
  const OperatingPointAnalysis& op = in.op;
  const SpeedSweepResult& sweep = in.sweep;
  const RattleIndices& r = op.rattle;
  const SolverSummary& s = op.result.summary;
  std::ostringstream h;
  h << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>"
    << Html(spec.name) << " - gearnvh report</title>\n"
    << kReportStyle << "\n</head><body>\n";
  h << "<h1>" << Html(spec.name) << "</h1>\n<p>" << Html(in.file) << " &middot; modal model "
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
    << Row("face load factor K_Hβ: slice model / ISO 6336-1 formula",
           fmt::format("{} / {}", Number(model.cycle.face.factor),
                       Number(model.cycle.face.iso_method_c)))
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
    << Row("dynamic factor",
           Number(op.te.dynamic_factor) + (factor_note.empty() ? "" : " (" + factor_note + ")"))
    << Row("rattle regime", RattleRegimeName(r.regime))
    << Row("impacts per mesh cycle (drive / back)",
           fmt::format("{} / {}", Number(r.drive_impacts_per_cycle),
                       Number(r.back_impacts_per_cycle)))
    << Row("impacts per second (drive / back)",
           fmt::format("{} / {}", Number(r.drive_impacts_per_second),
                       Number(r.back_impacts_per_second)))
    << Row("impact velocity RMS / max (mm/s)",
           fmt::format("{} / {}", Number(r.impact_velocity_rms * 1e3),
                       Number(r.impact_velocity_max * 1e3)))
    << Row("impact energy per mesh cycle (J)", Number(r.impact_energy_per_cycle))
    << Row("impact energy per second (mW)", Number(r.impact_energy_per_second * 1e3))
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
      << (k < static_cast<int>(in.modes.frequencies_hz.size())
              ? Number(in.modes.frequencies_hz[k], 5)
              : "-")
      << "</td>";
  }
  h << "</tr>\n";
  for (const ReducedModel& t : in.tiers) {
    h << "<tr><td>" << Html(t.name) << "</td><td>" << t.dof << "</td><td>"
      << StateDimension(model, t, spec.operating.excitation) << "</td><td>";
    const std::optional<double> error = ComplianceErrorVsFull(t.tier, t.compliance_error_vs_full);
    h << (error ? Number(100.0 * *error, 3) + " %" : "n/a") << "</td>";
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
  h << "</table>\n<h2>Speed sweep</h2>\n<p>" << SweepSpeedsHtml(sweep.points, "speeds")
    << ". Per speed: waterfall.csv; in results.json: sweep.</p>\n";
  h << "<h2>Mesh harmonics and sidebands of the TE</h2>\n<p>Plotted as stems in "
       "<a href=\"#sidebands.png\">sidebands.png</a>.</p>\n<details><summary>"
    << op.sidebands.size()
    << " lines</summary>\n<table>\n<tr><th>line</th>"
       "<th>frequency (Hz)</th><th>amplitude (µm)</th><th>dB re 1 µm</th></tr>\n";
  for (const SidebandRow& row : op.sidebands) {
    h << "<tr><td>" << Html(row.label) << "</td><td>" << Number(row.frequency_hz, 6) << "</td><td>"
      << Number(row.amplitude * 1e6) << "</td><td>" << Number(row.db_re_1um, 4) << "</td></tr>\n";
  }
  if (op.sidebands.empty()) h << "<tr><td colspan=\"4\">too few recorded cycles</td></tr>\n";
  h << "</table>\n</details>\n";
  if (const AtlasResult* atlas = in.atlas) {
    std::map<std::string, int> regimes;
    for (const AtlasCell& c : atlas->cells) ++regimes[c.ok ? RattleRegimeName(c.regime) : "failed"];
    h << "<h2>Chaos atlas</h2>\n<p>" << atlas->x.range.points << " x " << atlas->y.range.points
      << " cells (" << Html(atlas->x.parameter) << " x " << Html(atlas->y.parameter) << "), "
      << in.atlas_cycles << " mesh cycles each: ";
    for (const auto& [name, count] : regimes) h << Html(name) << " " << count << "; ";
    h << "<a href=\"atlas.csv\">atlas.csv</a></p>\n";
  }
  h << in.whine_html;
  h << "<h2>Figures</h2>\n";
  for (const ReportFigure& f : in.figures) {
    h << "<figure id=\"" << f.file << "\"><img src=\"" << f.file << "\" alt=\"" << Html(f.caption)
      << "\"><figcaption>" << Html(f.caption) << "</figcaption></figure>\n";
  }
  h << "<h2>Data</h2>\n<p>";
  for (const char* csv :
       {"te_trace.csv", "spectrum.csv", "sidebands.csv", "mesh_cycle.csv", "campbell.csv",
        "critical_speeds.csv", "waterfall.csv", "order_tracks.csv", "results.uff"}) {
    h << "<a href=\"" << csv << "\">" << csv << "</a> ";
  }
  h << "</p>\n" << kImageCheckScript << "\n</body></html>\n";
  return h.str();
}

}  // namespace gearnvh::app
