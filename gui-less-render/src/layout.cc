#include "gearnvh/render/layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <string>

namespace gearnvh::render {

namespace {

std::string TwelveDigits(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.12g", v);
  return text;
}

}  // namespace

std::vector<std::optional<Box>> PlaceLabels(const std::vector<LabelRequest>& labels,
                                            const Box& area, const std::vector<Box>& obstacles,
                                            double gap) {
  std::vector<std::optional<Box>> out;
  std::vector<Box> taken = obstacles;
  for (const LabelRequest& l : labels) {
    const double w = l.width, h = l.height;
    std::optional<Box> placed;
    // Rings of candidates at gap, gap + h and gap + 2 h from the point: the nearest free one.
    for (int ring = 0; ring < 3 && !placed; ++ring) {
      const double d = gap + ring * h;
      // Lower-left corners of the candidate boxes.
      const double candidates[8][2] = {{l.x + d, l.y + d},       {l.x - d - w, l.y + d},
                                       {l.x + d, l.y - d - h},   {l.x - d - w, l.y - d - h},
                                       {l.x - 0.5 * w, l.y + d}, {l.x - 0.5 * w, l.y - d - h},
                                       {l.x + d, l.y - 0.5 * h}, {l.x - d - w, l.y - 0.5 * h}};
      for (const auto& c : candidates) {
        const Box b{c[0], c[1], c[0] + w, c[1] + h};
        if (!b.Inside(area)) continue;
        if (std::any_of(taken.begin(), taken.end(), [&](const Box& t) { return b.Overlaps(t); })) {
          continue;
        }
        placed = b;
        break;
      }
    }
    if (placed) taken.push_back(*placed);
    out.push_back(placed);
  }
  return out;
}

AxisRange AutoRange(const std::vector<double>& values, bool allow_log, double margin,
                    double decades_for_log, double max_decades) {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  bool positive = true;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
    positive = positive && v > 0.0;
  }
  if (!(lo <= hi)) return {0.0, 1.0, false};
  if (allow_log && positive && std::log10(hi / lo) >= decades_for_log) {
    lo = std::max(lo, hi * std::pow(10.0, -max_decades));
    const double pad = std::pow(hi / lo, margin);
    return {lo / pad, hi * pad, true};
  }
  if (hi == lo) {
    const double half = lo != 0.0 ? 0.1 * std::abs(lo) : 1.0;
    return {lo - half, hi + half, false};
  }
  const double pad = margin * (hi - lo);
  return {lo - pad, hi + pad, false};
}

std::vector<double> LogTicks(double lo, double hi) {
  std::vector<double> out;
  if (!(lo > 0.0 && hi > lo)) return out;
  const int first = static_cast<int>(std::floor(std::log10(lo)));
  const int last = static_cast<int>(std::ceil(std::log10(hi)));
  auto with = [&](std::initializer_list<double> mantissas) {
    out.clear();
    for (int e = first; e <= last; ++e) {
      for (double m : mantissas) {
        // Rounded to 12 digits so 3 x 10^-1 prints as 0.3, not 0.30000000000000004.
        const double t = std::stod(TwelveDigits(m * std::pow(10.0, e)));
        if (t >= lo * (1.0 - 1e-12) && t <= hi * (1.0 + 1e-12)) out.push_back(t);
      }
    }
  };
  with({1.0});
  if (out.size() < 3) with({1.0, 2.0, 5.0});
  if (out.size() < 2) with({1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0});
  return out;
}

AxisRange MakeRoomForLegend(const AxisRange& y, const AxisRange& x, const std::vector<double>& xs,
                            const std::vector<double>& ys, double width, double height) {
  if (!(height > 0.0 && height < 1.0) || !(width > 0.0) || xs.size() != ys.size()) return y;
  auto t = [&y](double v) { return y.log ? std::log10(v) : v; };
  const double lo = t(y.min), hi = t(y.max);
  auto tx = [&x](double v) { return x.log ? std::log10(v) : v; };
  const double x_band = tx(x.max) - width * (tx(x.max) - tx(x.min));
  double peak = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < xs.size(); ++i) {
    if (x.log && !(xs[i] > 0.0)) continue;
    if (!(tx(xs[i]) >= x_band && xs[i] <= x.max) || !std::isfinite(ys[i])) continue;
    if (y.log && !(ys[i] > 0.0)) continue;
    peak = std::max(peak, t(ys[i]));
  }
  const double corner = hi - height * (hi - lo);
  if (!(peak >= corner)) return y;  // nothing under the legend
  // The highest point just under the corner: peak = lo + (1 - height) (new_hi - lo), 2 % spare.
  const double new_hi = lo + 1.02 * (peak - lo) / (1.0 - height);
  AxisRange out = y;
  out.max = y.log ? std::pow(10.0, new_hi) : new_hi;
  return out;
}

}  // namespace gearnvh::render
