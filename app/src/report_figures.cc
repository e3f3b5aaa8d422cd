#include "report_figures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace gearnvh::app {

namespace {

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

}  // namespace

render::LinePlot CampbellFigure(const SpeedSweepResult& sweep) {
  render::LinePlot p;
  p.title = "Campbell diagram";
  p.x_label = "pinion speed (rpm)";
  p.y_label = "frequency (Hz)";
  std::vector<double> rpm;
  for (const SpeedPoint& s : sweep.points) rpm.push_back(s.speed_rpm);
  double top = 0.0;
  for (size_t k = 0; k < sweep.campbell.frequency_hz.size(); ++k) {
    render::Series s{k == 0 ? "tracked modes" : "", rpm, sweep.campbell.frequency_hz[k]};
    s.color = 0;
    for (double f : s.y) {
      if (std::isfinite(f)) top = std::max(top, f);
    }
    p.series.push_back(std::move(s));
  }
  int color = 1;
  for (const OrderLine& o : sweep.campbell.orders) {
    render::Series s{o.label, {}, {}, render::Series::Style::kDashed};
    s.color = color++;
    if (color == 3) ++color;  // vermillion is kept for the critical speeds
    s.width = 1.5;
    for (double r : rpm) {
      s.x.push_back(r);
      s.y.push_back(o.order * r / 60.0);
    }
    p.series.push_back(std::move(s));
  }
  render::Series critical{"critical speeds", {}, {}, render::Series::Style::kPoints};
  critical.color = 3;
  critical.width = 9.0;
  for (const CriticalSpeed& c : sweep.campbell.critical_speeds) {
    critical.x.push_back(c.speed_rpm);
    critical.y.push_back(c.frequency_hz);
    p.labels.push_back({c.speed_rpm, c.frequency_hz, fmt::format("{:.0f} rpm", c.speed_rpm)});
  }
  if (!critical.x.empty()) p.series.push_back(std::move(critical));
  if (!rpm.empty() && top > 0.0) {
    p.fixed_x = p.fixed_y = true;
    p.x_min = rpm.front();
    p.x_max = rpm.back();
    p.y_min = 0.0;
    p.y_max = 1.1 * top;
  }
  return p;
}

render::HeatMap WaterfallFigure(const SpeedSweepResult& sweep) {
  render::HeatMap h;
  h.title = "Waterfall: dynamic TE amplitude";
  h.x_label = "pinion order (-)";
  h.y_label = "pinion speed (rpm)";
  h.value_label = "dB re 1 µm";
  h.nx = std::max(1, sweep.order_bins);
  h.ny = static_cast<int>(sweep.points.size());
  h.x_min = -0.5 * sweep.order_step;
  h.x_max = (h.nx - 0.5) * sweep.order_step;
  const double first = sweep.points.front().speed_rpm, last = sweep.points.back().speed_rpm;
  const double step = h.ny > 1 ? (last - first) / (h.ny - 1) : 1.0;
  h.y_min = first - 0.5 * step;
  h.y_max = last + 0.5 * step;
  for (const SpeedPoint& s : sweep.points) {
    for (int k = 0; k < h.nx; ++k) {
      const double a = s.ok && k < static_cast<int>(s.amplitude_m.size()) ? s.amplitude_m[k] : kNan;
      h.values.push_back(a > 0.0 ? 20.0 * std::log10(a / 1e-6) : kNan);
    }
  }
  // Keep the colour range on the signal: floor 60 dB below the strongest line.
  double top = -1e300;
  for (double v : h.values) {
    if (std::isfinite(v)) top = std::max(top, v);
  }
  for (double& v : h.values) {
    if (std::isfinite(v)) v = std::max(v, top - 60.0);
  }
  return h;
}

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

render::HeatMap AtlasFigure(const AtlasResult& atlas, bool lyapunov, const GearboxSpec& spec) {
  render::HeatMap h;
  const DisplayAxis ax = DisplayAxisFor(atlas.x.parameter, spec);
  const DisplayAxis ay = DisplayAxisFor(atlas.y.parameter, spec);
  h.title = lyapunov ? "Chaos atlas: largest Lyapunov exponent" : "Chaos atlas: rattle index";
  h.x_label = ax.label;
  h.y_label = ay.label;
  h.value_label = lyapunov ? "per forcing cycle" : "log10 J per forcing cycle";
  h.diverging = lyapunov;
  h.nx = atlas.x.range.points;
  h.ny = atlas.y.range.points;
  auto edges = [](const AtlasAxis& a, double scale, double& lo, double& hi) {
    const double from = a.range.from * scale, to = a.range.to * scale;
    const double step = a.range.points > 1 ? (to - from) / (a.range.points - 1) : 1.0;
    lo = from - 0.5 * step;
    hi = to + 0.5 * step;
  };
  edges(atlas.x, ax.scale, h.x_min, h.x_max);
  edges(atlas.y, ay.scale, h.y_min, h.y_max);
  // Strongly attracting cells (contact, lambda T_f ~ -60) would wash out the chaotic ones
  // (~ +3): the exponent is saturated at -max(largest positive value, 1).
  double positive = 1.0;
  for (const AtlasCell& c : atlas.cells) {
    if (c.ok) positive = std::max(positive, c.lyapunov_per_forcing_cycle);
  }
  for (const AtlasCell& c : atlas.cells) {
    if (!c.ok) {
      h.values.push_back(kNan);
    } else if (lyapunov) {
      h.values.push_back(std::max(c.lyapunov_per_forcing_cycle, -positive));
    } else {
      h.values.push_back(c.rattle_index > 0.0 ? std::log10(c.rattle_index) : kNan);
    }
  }
  return h;
}

}  // namespace gearnvh::app
