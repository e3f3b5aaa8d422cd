#include "report_whine.h"

#include <fmt/format.h>

#include <cmath>
#include <complex>
#include <sstream>

#include "atomic_file.h"
#include "finite_results.h"
#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/analysis/train_sweep.h"
#include "gearnvh/analysis/whine.h"
#include "gearnvh/analysis/written_numbers.h"
#include "report_gearbox.h"
#include "report_html.h"
#include "report_sweep_figures.h"
#include "whine_command.h"

namespace gearnvh::app {
namespace {

// The line at k times mesh i's order, or lines.size() when there is none.
size_t OwnLine(const WhineResult& r, double mesh_order, int k) {
  for (size_t l = 0; l < r.lines.size(); ++l) {
    if (std::abs(r.lines[l].order - k * mesh_order) <= 1e-9 * k * mesh_order) return l;
  }
  return r.lines.size();
}

OrderTrack Track(const WhineResult& r, size_t mesh, size_t line, const std::string& label) {
  OrderTrack t{label, r.lines[line].order, {}, r.meshes[mesh].te_amplitude_m[line]};
  for (double w : r.speed_rad_s) t.speed_rpm.push_back(Rpm(w));
  return t;
}

// Per bearing, the RMS over the lines of its force vector, sqrt(sum |F|^2 / 2), against speed.
render::LinePlot BearingFigure(const WhineResult& r, const std::string& reference) {
  render::LinePlot p;
  p.title = "Whine (mean model): dynamic bearing force on the housing, RMS over the lines";
  p.x_label = reference + " speed (rpm)";
  p.y_label = "force RMS (N)";
  p.log_x = r.speed_scale == AxisScale::kLog;
  for (const WhineBearing& b : r.bearings) {
    render::Series s{WhineBearingName(b), {}, {}};
    for (size_t k = 0; k < r.speed_rad_s.size(); ++k) {
      double sum = 0.0;
      for (const auto& line : b.force_amplitude_n) {
        for (const auto& direction : line) sum += 0.5 * direction[k] * direction[k];
      }
      s.x.push_back(Rpm(r.speed_rad_s[k]));
      s.y.push_back(std::sqrt(sum));
    }
    p.series.push_back(std::move(s));
  }
  return p;
}

// The waterfall of mesh `mesh` drawn from the lines: per speed a row of bins `step` orders apart,
// each line's TE amplitude in its nearest bin (the largest when two share one), the bins between
// lines at the figure's floor (1e-300 m: 60 dB under the strongest line once drawn).
struct LineWaterfall {
  std::vector<std::vector<double>> rows;
  WaterfallView view;
  int bins = 0;
};
LineWaterfall WaterfallOf(const WhineResult& r, size_t mesh, double step) {
  LineWaterfall w;
  w.bins = static_cast<int>(std::ceil(1.05 * r.lines.back().order / step)) + 1;
  w.rows.assign(r.speed_rad_s.size(), std::vector<double>(static_cast<size_t>(w.bins), 1e-300));
  for (size_t l = 0; l < r.lines.size(); ++l) {
    const auto bin = static_cast<size_t>(std::lround(r.lines[l].order / step));
    for (size_t s = 0; s < r.speed_rad_s.size(); ++s)
      w.rows[s][bin] = std::max(w.rows[s][bin], r.meshes[mesh].te_amplitude_m[l][s]);
  }
  w.view.order_step = step;
  for (size_t s = 0; s < r.speed_rad_s.size(); ++s) {
    w.view.speed_rpm.push_back(Rpm(r.speed_rad_s[s]));
    w.view.rows.push_back(&w.rows[s]);
  }
  return w;
}

// The page's table: per mesh its 1x and 2x mesh orders' peak TE and force, and the speeds where
// it may lose contact.
std::string Section(const WhineResult& r, const std::vector<double>& mesh_orders) {
  std::ostringstream h;
  h << "<h2>Whine (frequency domain, mean mesh stiffness)</h2>\n<p>" << r.speed_rad_s.size()
    << " speeds at " << Html(TierName(r.tier))
    << ", every mesh in contact at its mean stiffness, driven by its loaded static TE, runout, "
       "pitch errors and the excitation orders (docs/design.md §14; every line in "
       "<a href=\"whine.json\">whine.json</a>, <a href=\"whine_meshes.csv\">whine_meshes.csv</a>"
    << (r.bearings.empty() ? "" : ", <a href=\"whine_bearings.csv\">whine_bearings.csv</a>")
    << ").</p>\n<table>\n<tr><th>mesh</th><th>line</th><th>peak TE (µm)</th><th>at (rpm)</th>"
       "<th>peak force (N)</th><th>speeds that may lose contact (of all)</th></tr>\n";
  for (size_t i = 0; i < r.meshes.size(); ++i) {
    const WhineMesh& m = r.meshes[i];
    size_t flagged = 0;
    for (bool f : m.contact_loss) flagged += f ? 1 : 0;
    for (int k = 1; k <= 2; ++k) {
      const size_t l = OwnLine(r, mesh_orders[i], k);
      if (l == r.lines.size()) continue;
      const auto& te = m.te_amplitude_m[l];
      const size_t at = static_cast<size_t>(std::max_element(te.begin(), te.end()) - te.begin());
      const auto& force = m.force_amplitude_n[l];
      h << "<tr><td>" << Html(m.name) << "</td><td>" << Html(r.lines[l].label) << "</td><td>"
        << Number(te[at] * 1e6) << "</td><td>" << Number(Rpm(r.speed_rad_s[at]), 5) << "</td><td>"
        << Number(*std::max_element(force.begin(), force.end())) << "</td><td>" << flagged << " of "
        << m.contact_loss.size() << "</td></tr>\n";
    }
  }
  h << "</table>\n";
  return h.str();
}

}  // namespace

WhineReport BuildWhineReport(const TrainSpec& spec, Tier tier, int threads,
                             const std::filesystem::path& folder,
                             const render::ImageOptions& image) {
  WhineOptions options;
  options.tier = tier;
  options.speeds = kReportWhineSpeeds;
  options.threads = threads;
  const WhineResult r = RunWhine(spec, options);
  const std::vector<double> mesh_orders = MeshOrders(spec);
  WhineReport report;
  std::vector<OrderTrack> first, second;
  for (size_t i = 0; i < r.meshes.size(); ++i) {
    for (int k = 1; k <= 2; ++k) {
      const size_t l = OwnLine(r, mesh_orders[i], k);
      if (l == r.lines.size()) continue;
      (k == 1 ? first : second)
          .push_back(Track(r, i, l, fmt::format("{}x mesh {}", k, r.meshes[i].name)));
    }
  }
  const std::string reference = spec.operating.input_shaft;
  const auto draw = [&](const std::string& name, const std::string& caption,
                        const render::RenderStatus& status) {
    ThrowUnlessDrawn(name, status);
    report.figures.push_back({name, caption});
  };
  draw("whine_te.png",
       "Whine in the frequency domain (mean mesh stiffness): TE amplitude at each mesh's 1x mesh "
       "order (solid) and 2x (dashed, same colour) against the input speed, " +
           std::to_string(r.speed_rad_s.size()) + " speeds (whine_meshes.csv holds every line).",
       render::RenderLinePlot(OrderTrackFigure(first, second, r.speed_scale,
                                               "Whine (mean model): TE at each mesh's 1x and 2x "
                                               "mesh order",
                                               reference, DashedColours::kAsSolid),
                              image, (folder / "whine_te.png").string()));
  // Bins a quarter order apart, finer when the lowest line is below half an order, but at most
  // 4000 bins (an image is not finer).
  const double step =
      std::max(std::min(0.25, 0.5 * r.lines.front().order), r.lines.back().order / 4000.0);
  for (size_t i = 0; i < r.meshes.size(); ++i) {
    const LineWaterfall w = WaterfallOf(r, i, step);
    const std::string name = fmt::format("whine_waterfall_{}.png", i + 1);
    draw(name,
         fmt::format("Whine waterfall of mesh {}: its TE amplitude at every line (input orders) "
                     "against the input speed, dB re 1 µm, floored 60 dB under its strongest "
                     "line (whine_meshes.csv).",
                     r.meshes[i].name),
         render::RenderHeatMap(WaterfallFigure(w.view, w.bins, r.speed_scale, reference,
                                               "Whine waterfall: TE of mesh " + r.meshes[i].name),
                               image, (folder / name).string()));
  }
  if (!r.bearings.empty()) {
    draw("whine_bearings.png",
         "Whine: each bearing's dynamic force on the housing, the RMS of its force vector over "
         "every line, against the input speed (whine_bearings.csv: per line and direction).",
         render::RenderLinePlot(BearingFigure(r, reference), image,
                                (folder / "whine_bearings.png").string()));
  }
  nlohmann::json doc = WhineJson(r);
  doc["name"] = spec.name;
  doc["input_shaft"] = reference;
  RequireFinite(doc, "whine.json");
  WriteFileAtomically((folder / "whine.json").string(), doc.dump(1) + "\n");
  WriteFileAtomically((folder / "whine_meshes.csv").string(), WhineMeshesCsv(r));
  if (!r.bearings.empty())
    WriteFileAtomically((folder / "whine_bearings.csv").string(), WhineBearingsCsv(r));
  report.summary = {{"file", "whine.json"},
                    {"tier", TierName(r.tier)},
                    {"speeds", r.speed_rad_s.size()},
                    {"contact_loss_speeds", r.ContactLossSpeeds()},
                    {"warnings", r.warnings}};
  report.html = Section(r, mesh_orders);
  return report;
}

}  // namespace gearnvh::app
