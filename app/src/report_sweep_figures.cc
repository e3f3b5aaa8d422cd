#include "report_sweep_figures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "display_units.h"

namespace gearnvh::app {

namespace {

// A point without a value: the plots leave it out.
constexpr double kNoValue = std::numeric_limits<double>::quiet_NaN();

// Palette indices (plots.h PaletteColor): blue, orange, green, vermillion, sky, purple, grey.
int TypeColor(ModeType t) {
  switch (t) {
    case ModeType::kTorsional:
      return 0;
    case ModeType::kLateral:
      return 2;
    case ModeType::kAxial:
      return 5;
    case ModeType::kCoupled:
      return 4;
    case ModeType::kUnknown:
      break;
  }
  return 6;
}

// "3 lateral fw": the mode's number from 1, its type and whirl, short enough to label a line.
std::string ModeTag(int mode, const ModeInfo& info) {
  std::string tag = fmt::format("{} {}", mode + 1, ModeTypeName(info.type));
  if (info.whirl == Whirl::kForward) tag += " fw";
  if (info.whirl == Whirl::kBackward) tag += " bw";
  return tag;
}

// The last finite point of a series (its right end), or false.
bool LastPoint(const std::vector<double>& x, const std::vector<double>& y, double& px, double& py) {
  for (size_t i = y.size(); i-- > 0;) {
    if (std::isfinite(y[i]) && y[i] > 0.0) {
      px = x[i];
      py = y[i];
      return true;
    }
  }
  return false;
}

// The outer cell edges of a grid on `range` (values times `scale`): half a step beyond the ends,
// the step a difference (linear) or a ratio (log).
void CellEdges(const SweepRange& range, double scale, double& lo, double& hi) {
  const double from = range.from * scale, to = range.to * scale;
  if (range.scale == AxisScale::kLog) {
    const double ratio = range.points > 1 ? std::pow(to / from, 1.0 / (range.points - 1)) : 2.0;
    lo = from / std::sqrt(ratio);
    hi = to * std::sqrt(ratio);
    return;
  }
  const double step = range.points > 1 ? (to - from) / (range.points - 1) : 1.0;
  lo = from - 0.5 * step;
  hi = to + 0.5 * step;
}

}  // namespace

render::LinePlot CampbellFigure(const SpeedSweepResult& sweep) {
  std::vector<double> rpm;
  for (const SpeedPoint& s : sweep.points) rpm.push_back(s.speed_rpm);
  return CampbellFigure(sweep.campbell, rpm, sweep.speed_scale, "pinion speed (rpm)");
}

render::LinePlot CampbellFigure(const CampbellData& c, const std::vector<double>& rpm,
                                AxisScale speed_scale, const std::string& speed_label) {
  render::LinePlot p;
  p.title = "Campbell diagram: every tracked mode";
  p.x_label = speed_label;
  p.y_label = "frequency (Hz)";
  p.log_y = true;
  // Labels in order of importance (the layout drops the later ones first when crowded):
  // critical speeds, order lines, modes.
  render::Series critical{"critical speeds", {}, {}, render::Series::Style::kPoints};
  critical.color = 3;
  critical.width = 9.0;
  for (const CriticalSpeed& s : c.critical_speeds) {
    critical.x.push_back(s.speed_rpm);
    critical.y.push_back(s.frequency_hz);
    p.labels.push_back(
        {s.speed_rpm, s.frequency_hz, fmt::format("{:.0f} rpm, mode {}", s.speed_rpm, s.mode + 1)});
  }
  bool mesh_named = false, shaft_named = false;
  for (const OrderLine& o : c.orders) {
    const bool mesh = o.label.find("mesh") != std::string::npos;
    std::string legend;
    if (mesh && !mesh_named) legend = "mesh orders", mesh_named = true;
    if (!mesh && !shaft_named) legend = "shaft orders", shaft_named = true;
    render::Series s{legend, {}, {}, render::Series::Style::kDashed};
    s.color = mesh ? 1 : 6;
    s.width = 1.5;
    for (double r : rpm) {
      s.x.push_back(r);
      s.y.push_back(o.order * r / 60.0);
    }
    double lx = 0.0, ly = 0.0;
    if (LastPoint(s.x, s.y, lx, ly)) p.labels.push_back({lx, ly, o.label});
    p.series.push_back(std::move(s));
  }
  std::vector<bool> type_named(5, false);
  for (size_t k = 0; k < c.frequency_hz.size(); ++k) {
    const ModeInfo info = k < c.modes.size() ? c.modes[k] : ModeInfo{};
    const int t = static_cast<int>(info.type);
    std::string legend;
    if (!type_named[t]) {
      legend = std::string(ModeTypeName(info.type)) + " modes";
      type_named[t] = true;
    }
    render::Series s{legend, rpm, c.frequency_hz[k]};
    s.color = TypeColor(info.type);
    double lx = 0.0, ly = 0.0;
    if (LastPoint(s.x, s.y, lx, ly)) {
      p.labels.push_back({lx, ly, ModeTag(static_cast<int>(k), info)});
    }
    p.series.push_back(std::move(s));
  }
  if (!critical.x.empty()) p.series.push_back(std::move(critical));
  p.log_x = speed_scale == AxisScale::kLog;
  if (rpm.size() >= 2) {
    p.fixed_x = true;
    p.x_min = rpm.front();
    p.x_max = rpm.back();
  }
  return p;
}

render::HeatMap WaterfallFigure(const SpeedSweepResult& sweep) {
  return WaterfallFigure(PairWaterfall(sweep), sweep.order_bins, sweep.speed_scale, "pinion",
                         "Waterfall: dynamic TE amplitude");
}

render::HeatMap WaterfallFigure(const WaterfallView& waterfall, int order_bins,
                                AxisScale speed_scale, const std::string& reference,
                                const std::string& title) {
  render::HeatMap h;
  h.title = title;
  h.x_label = reference + " order (-)";
  h.y_label = reference + " speed (rpm)";
  h.value_label = "dB re 1 µm";
  h.nx = std::max(1, order_bins);
  h.ny = static_cast<int>(waterfall.rows.size());
  h.x_min = -0.5 * waterfall.order_step;
  h.x_max = (h.nx - 0.5) * waterfall.order_step;
  const SweepRange rpm{waterfall.speed_rpm.front(), waterfall.speed_rpm.back(), h.ny, speed_scale};
  CellEdges(rpm, 1.0, h.y_min, h.y_max);
  h.log_y = speed_scale == AxisScale::kLog;
  for (const std::vector<double>* row : waterfall.rows) {
    for (int k = 0; k < h.nx; ++k) {
      const double a = row != nullptr && k < static_cast<int>(row->size()) ? (*row)[k] : kNoValue;
      h.values.push_back(a > 0.0 ? 20.0 * std::log10(a / 1e-6) : kNoValue);
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

render::LinePlot OrderTrackFigure(const std::vector<OrderTrack>& solid,
                                  const std::vector<OrderTrack>& dashed, AxisScale speed_scale,
                                  const std::string& title, const std::string& reference,
                                  DashedColours colours) {
  render::LinePlot p;
  p.log_x = speed_scale == AxisScale::kLog;
  p.title = title;
  p.x_label = reference + " speed (rpm)";
  p.y_label = "TE amplitude (dB re 1 µm)";
  p.auto_log_y = false;
  double top = -std::numeric_limits<double>::infinity();
  for (const auto* tracks : {&solid, &dashed}) {
    for (const OrderTrack& t : *tracks) {
      for (double a : t.amplitude_m) {
        if (a > 0.0) top = std::max(top, 20.0 * std::log10(a / 1e-6));
      }
    }
  }
  auto add = [&](const OrderTrack& t, render::Series::Style style, int color, double width) {
    render::Series s{t.label, t.speed_rpm, {}, style};
    for (double a : t.amplitude_m) {
      const double db = a > 0.0 ? 20.0 * std::log10(a / 1e-6) : kNoValue;
      s.y.push_back(db >= top - 100.0 ? db : kNoValue);
    }
    s.color = color;
    s.width = width;
    p.series.push_back(std::move(s));
  };
  int color = 0;
  for (const OrderTrack& t : solid) add(t, render::Series::Style::kLine, color++, 2.0);
  color = colours == DashedColours::kAfterSolid ? 3 : 0;
  for (const OrderTrack& t : dashed) add(t, render::Series::Style::kDashed, color++, 1.5);
  return p;
}

std::string OrderTracksCsv(const std::vector<OrderTrack>& solid,
                           const std::vector<OrderTrack>& dashed, const std::string& reference) {
  std::vector<const OrderTrack*> all;
  for (const auto* tracks : {&solid, &dashed}) {
    for (const OrderTrack& t : *tracks) all.push_back(&t);
  }
  std::ostringstream os;
  os.precision(12);
  os << "speed_rpm";
  for (const OrderTrack* t : all) {
    os << ",\"" << t->label << " (" << reference << " order " << t->order << ") m\",\"" << t->label
       << " dB re 1 µm\"";
  }
  os << '\n';
  const size_t n = all.empty() ? 0 : all.front()->speed_rpm.size();
  for (size_t i = 0; i < n; ++i) {
    os << all.front()->speed_rpm[i];
    for (const OrderTrack* t : all) {
      const double a = t->amplitude_m[i];
      if (a > 0.0) {
        os << ',' << a << ',' << 20.0 * std::log10(a / 1e-6);
      } else {
        os << ",,";
      }
    }
    os << '\n';
  }
  return os.str();
}

render::HeatMap AtlasFigure(const AtlasResult& atlas, bool lyapunov, const GearboxSpec& spec) {
  render::HeatMap h;
  const DisplayAxis ax = DisplayAxisFor(atlas.x.parameter, spec);
  const DisplayAxis ay = DisplayAxisFor(atlas.y.parameter, spec);
  h.title = lyapunov ? "Chaos atlas: largest Lyapunov exponent" : "Chaos atlas: rattle index";
  h.x_label = ax.label;
  h.y_label = ay.label;
  // Grey cells (NaN) are part of the colour key: the figure says what they mean.
  h.value_label = lyapunov ? "per forcing cycle; grey: failed cell"
                           : "log10 J per forcing cycle; grey: no impact or failed cell";
  h.diverging = lyapunov;
  h.nx = atlas.x.range.points;
  h.ny = atlas.y.range.points;
  CellEdges(atlas.x.range, ax.scale, h.x_min, h.x_max);
  CellEdges(atlas.y.range, ay.scale, h.y_min, h.y_max);
  h.log_x = atlas.x.range.scale == AxisScale::kLog;
  h.log_y = atlas.y.range.scale == AxisScale::kLog;
  // Strongly attracting cells (contact, lambda T_f ~ -60) would wash out the chaotic ones
  // (~ +3): the exponent is saturated at -max(largest positive value, 1).
  double positive = 1.0;
  for (const AtlasCell& c : atlas.cells) {
    if (c.ok) positive = std::max(positive, c.lyapunov_per_forcing_cycle);
  }
  for (const AtlasCell& c : atlas.cells) {
    if (!c.ok) {
      h.values.push_back(kNoValue);
    } else if (lyapunov) {
      h.values.push_back(std::max(c.lyapunov_per_forcing_cycle, -positive));
    } else {
      h.values.push_back(c.rattle_index > 0.0 ? std::log10(c.rattle_index) : kNoValue);
    }
  }
  return h;
}

render::LinePlot TierComparisonFigure(const std::string& cost_label,
                                      const std::vector<TierPoint>& tiers,
                                      const std::string& second_error_label) {
  render::LinePlot p;
  p.title = "Modal tiers: accuracy against cost";
  p.x_label = cost_label;
  p.y_label = "error magnitude (%)";
  p.log_x = p.log_y = true;
  render::Series frequency{
      "largest natural-frequency error", {}, {}, render::Series::Style::kPoints};
  frequency.width = 11.0;
  frequency.color = 0;
  render::Series positive{second_error_label, {}, {}, render::Series::Style::kPoints};
  positive.width = 8.0;
  positive.color = 3;
  render::Series negative{second_error_label + " < 0", {}, {}, render::Series::Style::kPoints};
  negative.width = 10.0;
  negative.color = 5;
  negative.marker = render::Series::Marker::kDiamond;
  auto shown = [](double error) {
    constexpr double kFloor = 1e-6;  // %
    return std::isfinite(error) ? std::max(100.0 * std::abs(error), kFloor) : kNoValue;
  };
  for (const TierPoint& t : tiers) {
    const double f = shown(t.frequency_error);
    const double e = t.second_error ? shown(*t.second_error) : kNoValue;
    if (std::isfinite(f)) {
      frequency.x.push_back(t.cost);
      frequency.y.push_back(f);
    }
    if (std::isfinite(e)) {
      render::Series& s = *t.second_error < 0.0 ? negative : positive;
      s.x.push_back(t.cost);
      s.y.push_back(e);
    }
    // The name at the frequency error, or at the second error when that one cannot be drawn.
    p.labels.push_back({t.cost, std::isfinite(f) ? f : e, t.name});
  }
  p.series = {frequency};
  for (render::Series* s : {&positive, &negative}) {
    if (!s->x.empty()) p.series.push_back(std::move(*s));
  }
  return p;
}

}  // namespace gearnvh::app
