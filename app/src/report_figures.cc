#include "report_figures.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

namespace gearnvh::app {

namespace {

// A NaN point ends one stem of a line plot before the next starts.
constexpr double kStemBreak = std::numeric_limits<double>::quiet_NaN();

}  // namespace

render::LinePlot SpectrumFigure(const OperatingPointAnalysis& op) {
  render::LinePlot p;
  p.title = "Dynamic TE spectrum, mesh harmonics and sidebands";
  p.x_label = "frequency (Hz)";
  p.y_label = "TE amplitude (µm)";
  p.log_y = true;
  const double mesh_hz = 1.0 / op.tables.mesh_period;
  render::Series line{"TE spectrum", {}, {}};
  line.width = 1.5;
  double top = 0.0;
  for (size_t k = 1; k < op.spectrum.amplitude.size(); ++k) {
    const double f = static_cast<double>(k) * op.spectrum.bin_hz;
    if (f > 3.5 * mesh_hz) break;
    line.x.push_back(f);
    line.y.push_back(op.spectrum.amplitude[k] * 1e6);
    top = std::max(top, op.spectrum.amplitude[k] * 1e6);
  }
  p.series.push_back(std::move(line));
  render::Series marks{"mesh harmonics and sidebands", {}, {}, render::Series::Style::kPoints};
  marks.color = 3;
  marks.width = 8.0;
  std::vector<const SidebandRow*> rows;
  for (const SidebandRow& r : op.sidebands) {
    if (r.amplitude * 1e6 < 1e-4 * top) continue;  // below the plot's useful range
    marks.x.push_back(r.frequency_hz);
    marks.y.push_back(r.amplitude * 1e6);
    rows.push_back(&r);
  }
  std::sort(rows.begin(), rows.end(),
            [](const SidebandRow* a, const SidebandRow* b) { return a->amplitude > b->amplitude; });
  for (size_t i = 0; i < rows.size() && i < 6; ++i) {
    p.labels.push_back({rows[i]->frequency_hz, rows[i]->amplitude * 1e6, rows[i]->label});
  }
  if (!marks.x.empty()) p.series.push_back(std::move(marks));
  if (top > 0.0) {
    p.fixed_y = true;
    p.y_min = std::max(1e-6 * top, 1e-12);
    p.y_max = 3.0 * top;
  }
  return p;
}

render::LinePlot SidebandStemFigure(const OperatingPointAnalysis& op) {
  render::LinePlot p;
  p.title = "Mesh harmonics and shaft-order sidebands of the TE";
  p.x_label = "frequency (Hz)";
  p.y_label = "TE amplitude (dB re 1 µm)";
  p.auto_log_y = false;
  double top = -std::numeric_limits<double>::infinity();
  for (const SidebandRow& r : op.sidebands) top = std::max(top, r.db_re_1um);
  if (!std::isfinite(top)) return p;
  // A mesh harmonic's label names fm without a sideband sign ("2 fm"; sidebands read
  // "1 fm + 1 f1", shaft orders "2 f1").
  auto harmonic = [](const SidebandRow& r) {
    return r.label.find("fm") != std::string::npos && r.label.find(" + ") == std::string::npos &&
           r.label.find(" - ") == std::string::npos;
  };
  std::vector<const SidebandRow*> shown;
  double bottom = top;
  for (const SidebandRow& r : op.sidebands) {
    if (!(r.db_re_1um >= top - 80.0)) continue;
    shown.push_back(&r);
    bottom = std::min(bottom, r.db_re_1um);
  }
  const double base = bottom - 5.0;
  // Stems as one line per kind broken by NaN (drawn as gaps), heads as points.
  render::Series stems[2] = {{"", {}, {}}, {"", {}, {}}};
  render::Series heads[2] = {
      {"mesh harmonics", {}, {}, render::Series::Style::kPoints},
      {"shaft orders and sidebands", {}, {}, render::Series::Style::kPoints}};
  for (const SidebandRow* r : shown) {
    const int kind = harmonic(*r) ? 0 : 1;
    stems[kind].x.insert(stems[kind].x.end(), {r->frequency_hz, r->frequency_hz, r->frequency_hz});
    stems[kind].y.insert(stems[kind].y.end(), {base, r->db_re_1um, kStemBreak});
    heads[kind].x.push_back(r->frequency_hz);
    heads[kind].y.push_back(r->db_re_1um);
  }
  for (int kind = 0; kind < 2; ++kind) {
    stems[kind].color = heads[kind].color = kind == 0 ? 0 : 3;
    stems[kind].width = 2.0;
    heads[kind].width = 8.0;
    if (!heads[kind].x.empty()) p.series.push_back(stems[kind]);
  }
  for (int kind = 0; kind < 2; ++kind) {
    if (!heads[kind].x.empty()) p.series.push_back(heads[kind]);
  }
  std::stable_sort(shown.begin(), shown.end(), [&](const SidebandRow* a, const SidebandRow* b) {
    if (harmonic(*a) != harmonic(*b)) return harmonic(*a);
    return a->amplitude > b->amplitude;
  });
  for (size_t i = 0; i < shown.size() && i < 12; ++i) {
    p.labels.push_back({shown[i]->frequency_hz, shown[i]->db_re_1um, shown[i]->label});
  }
  p.fixed_y = true;
  p.y_min = base;
  p.y_max = top + 0.12 * (top - base) + 3.0;  // room for the labels above the strongest
  return p;
}

render::LinePlot TeTraceFigure(const OperatingPointAnalysis& op, long cycles) {
  render::LinePlot p;
  p.title = fmt::format("Dynamic transmission error, last {} mesh cycles", cycles);
  p.x_label = "time (ms)";
  p.y_label = "TE (µm)";
  const auto& samples = op.result.trajectory.samples;
  const size_t per_cycle = op.tables.boundaries.size() - 1;
  const size_t count = std::min(samples.size(), static_cast<size_t>(cycles) * per_cycle);
  render::Series te{"dynamic TE", {}, {}};
  const size_t first = samples.size() - count;
  const double t0 = count > 0 ? samples[first].time : 0.0;
  for (size_t i = first; i < samples.size(); ++i) {
    te.x.push_back(1e3 * (samples[i].time - t0));
    te.y.push_back(1e6 * samples[i].te);
  }
  p.series.push_back(std::move(te));
  // The flanks: drive contact above +b, back contact below -b (gap without the unloaded error).
  const double b = 1e6 * op.tables.half_backlash;
  if (count > 0) {
    const double span = p.series.front().x.back();
    for (double level : {b, -b}) {
      render::Series wall{level > 0 ? "+/- half backlash" : "",
                          {0.0, span},
                          {level, level},
                          render::Series::Style::kDashed};
      wall.color = 6;
      wall.width = 1.0;
      p.series.push_back(std::move(wall));
    }
  }
  return p;
}

render::LinePlot PhaseFigure(const OperatingPointAnalysis& op, long cycles,
                             long base_period_cycles) {
  render::LinePlot p;
  p.title = "Phase portrait and Poincaré section";
  p.x_label = "TE (µm)";
  p.y_label = "TE rate (mm/s)";
  const auto& samples = op.result.trajectory.samples;
  const size_t per_cycle = op.tables.boundaries.size() - 1;
  const size_t count = std::min(samples.size(), static_cast<size_t>(cycles) * per_cycle);
  render::Series orbit{"trajectory", {}, {}};
  orbit.width = 1.0;
  for (size_t i = samples.size() - count; i < samples.size(); ++i) {
    orbit.x.push_back(1e6 * samples[i].te);
    orbit.y.push_back(1e3 * samples[i].te_rate);
  }
  p.series.push_back(std::move(orbit));
  render::Series section{
      "Poincaré section (every " + Count(base_period_cycles, "mesh cycle", "mesh cycles") + ")",
      {},
      {},
      render::Series::Style::kPoints};
  section.color = 3;
  section.width = 6.0;
  const double T = op.tables.mesh_period;
  for (const TrajectorySample& s : samples) {
    const double c = s.time / T;
    const long whole = std::lround(c);
    if (std::abs(c - static_cast<double>(whole)) < 1e-6 && whole % base_period_cycles == 0) {
      section.x.push_back(1e6 * s.te);
      section.y.push_back(1e3 * s.te_rate);
    }
  }
  if (!section.x.empty()) p.series.push_back(std::move(section));
  return p;
}

namespace {

render::LinePlot CycleFigure(const std::string& title, const std::string& y_label) {
  render::LinePlot p;
  p.title = title;
  p.x_label = "mesh cycle fraction (-)";
  p.y_label = y_label;
  p.fixed_x = true;
  p.x_min = 0.0;
  p.x_max = 1.0;
  return p;
}

}  // namespace

render::LinePlot MeshStiffnessFigure(const ComponentModel& model) {
  render::LinePlot p = CycleFigure("Mesh stiffness over one mesh cycle", "stiffness (N/µm)");
  render::Series drive{"drive flank", model.cycle.tau, {}};
  for (const FlankSample& s : model.cycle.drive) drive.y.push_back(s.stiffness * 1e-6);
  render::Series back{"back flank", model.cycle.tau, {}, render::Series::Style::kDashed};
  for (const FlankSample& s : model.cycle.back) back.y.push_back(s.stiffness * 1e-6);
  p.series = {drive, back};
  return p;
}

render::LinePlot LoadSharingFigure(const ComponentModel& model) {
  render::LinePlot p =
      CycleFigure("Load sharing between tooth pairs (drive flank)", "load share (-)");
  int pairs = 0;
  for (const FlankSample& s : model.cycle.drive) pairs = std::max(pairs, s.pair_count);
  for (int j = 0; j < pairs; ++j) {
    render::Series s{fmt::format("pair {}", j + 1), model.cycle.tau, {}};
    for (const FlankSample& f : model.cycle.drive) {
      s.y.push_back(j < f.pair_count ? f.pairs[j].load_share : 0.0);
    }
    p.series.push_back(std::move(s));
  }
  p.fixed_y = true;
  p.y_min = 0.0;
  p.y_max = 1.05;
  return p;
}

render::LinePlot LsteFigure(const ComponentModel& model) {
  render::LinePlot p = CycleFigure("Loaded static transmission error (LSTE)", "mesh approach (µm)");
  render::Series s{"LSTE at the operating load", model.cycle.tau, {}};
  for (const FlankSample& f : model.cycle.drive) s.y.push_back(f.lste * 1e6);
  p.series = {s};
  return p;
}

render::LinePlot FaceLoadFigure(const std::vector<std::pair<std::string, FaceLoad>>& meshes) {
  render::LinePlot p;
  p.title = "Load across the face (drive flank, mesh-cycle mean)";
  p.x_label = "position from the face start (mm)";
  p.y_label = "line load (N/mm)";
  p.auto_log_y = false;
  for (const auto& [name, face] : meshes) {
    if (!face.modelled()) continue;
    render::Series s{fmt::format("{} (K_Hbeta {:.3f})", name, face.factor), {}, {}};
    for (size_t i = 0; i < face.position.size(); ++i) {
      s.x.push_back(face.position[i] * 1e3);
      s.y.push_back(face.line_load[i] * 1e-3);
    }
    p.series.push_back(s);
  }
  return p;
}

render::LinePlot CouplingTwistFigure(const TrainOperatingPoint& op, double window_s,
                                     size_t max_points) {
  constexpr double kDeg = 180.0 / std::numbers::pi;
  const TrainHistories& h = op.histories;
  render::LinePlot p;
  p.title = fmt::format("Coupling twist, last {:.3g} s", window_s);
  p.x_label = "time (s)";
  p.y_label = "twist (deg)";
  p.auto_log_y = false;
  const size_t pairs = std::max<size_t>(1, max_points / 2);  // a bucket draws two points
  // op.couplings (the exact statistics) is empty after a failed run.
  for (size_t c = 0; c < std::min(h.coupling_twist.size(), op.couplings.size()); ++c) {
    const std::vector<double>& twist = h.coupling_twist[c];
    render::Series s{op.couplings[c].name, {}, {}};
    const size_t shown = std::min(twist.size(), static_cast<size_t>(window_s / h.dt) + 1);
    const size_t bucket = shown <= max_points ? 1 : (shown + pairs - 1) / pairs;
    for (size_t first = twist.size() - shown; first < twist.size(); first += bucket) {
      const size_t last = std::min(twist.size(), first + bucket);
      const auto [low, high] = std::minmax_element(twist.begin() + static_cast<long>(first),
                                                   twist.begin() + static_cast<long>(last));
      for (auto k : low < high ? std::array{low, high} : std::array{high, low}) {
        s.x.push_back(h.start + static_cast<double>(k - twist.begin()) * h.dt);
        s.y.push_back(*k * kDeg);
        if (low == high) break;  // one sample
      }
    }
    if (s.x.empty()) continue;
    const double mean = op.couplings[c].twist.mean * kDeg;
    render::Series m{"", {s.x.front(), s.x.back()}, {mean, mean}, render::Series::Style::kDashed};
    m.color = static_cast<int>(c);
    m.width = 1.0;
    s.color = static_cast<int>(c);
    p.series.push_back(std::move(s));
    p.series.push_back(std::move(m));
  }
  return p;
}

}  // namespace gearnvh::app
