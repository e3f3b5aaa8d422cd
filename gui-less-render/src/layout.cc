#include "gearnvh/render/layout.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace gearnvh::render {

std::vector<std::optional<Box>> PlaceLabels(const std::vector<LabelRequest>& labels,
                                            const Box& area, const std::vector<Box>& obstacles,
                                            double gap) {
  std::vector<std::optional<Box>> out;
  std::vector<Box> taken = obstacles;
  for (const LabelRequest& l : labels) {
    const double w = l.width, h = l.height;
    // Lower-left corners of the candidate boxes.
    const double candidates[8][2] = {
        {l.x + gap, l.y + gap},           {l.x - gap - w, l.y + gap},
        {l.x + gap, l.y - gap - h},       {l.x - gap - w, l.y - gap - h},
        {l.x - 0.5 * w, l.y + gap},       {l.x - 0.5 * w, l.y - gap - h},
        {l.x + gap, l.y - 0.5 * h},       {l.x - gap - w, l.y - 0.5 * h}};
    std::optional<Box> placed;
    for (const auto& c : candidates) {
      const Box b{c[0], c[1], c[0] + w, c[1] + h};
      if (!b.Inside(area)) continue;
      if (std::any_of(taken.begin(), taken.end(), [&](const Box& t) { return b.Overlaps(t); })) {
        continue;
      }
      placed = b;
      break;
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

}  // namespace gearnvh::render
