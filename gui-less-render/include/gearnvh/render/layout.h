// Plot layout decisions, as plain geometry (no VTK): where text labels go so they overlap
// neither each other, the legend nor the data markers, and which range (linear with a margin, or
// logarithmic when the data span decades) an axis shows.
#pragma once

#include <optional>
#include <vector>

namespace gearnvh::render {

// An axis-aligned rectangle in pixels (y up, as VTK's scene).
struct Box {
  double x0 = 0.0, y0 = 0.0, x1 = 0.0, y1 = 0.0;
  bool Overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
  bool Inside(const Box& o) const { return x0 >= o.x0 && x1 <= o.x1 && y0 >= o.y0 && y1 <= o.y1; }
};

// A label of size (width, height) px that belongs to the point (x, y) px.
struct LabelRequest {
  double x = 0.0, y = 0.0, width = 0.0, height = 0.0;
};

// Places labels in request order (callers put the important ones first): each at the first of
// eight positions around its point (right-above, left-above, right-below, left-below, above,
// below, right, left; `gap` px away, then gap + h and gap + 2 h away for a label h px high) that
// lies inside `area` and overlaps neither a label placed before nor any of `obstacles` (the
// legend, data markers, samples of the lines). A label with no free position is dropped
// (nullopt): a missing label is better than an unreadable one.
std::vector<std::optional<Box>> PlaceLabels(const std::vector<LabelRequest>& labels,
                                            const Box& area, const std::vector<Box>& obstacles,
                                            double gap = 4.0);

struct AxisRange {
  double min = 0.0, max = 1.0;
  bool log = false;
};

// The range an axis shows for `values` (non-finite ones ignored): logarithmic when `allow_log`,
// every value is > 0 and max / min >= `decades_for_log` decades, showing at most `max_decades`
// below the maximum (rounding noise of an exact spectrum lies 15 decades down) and padded by the
// factor (max/min)^margin on both ends; otherwise linear, padded by margin * (max - min) (a
// constant signal gets +-10 % of its magnitude, or +-1 around 0). With no finite value: [0, 1].
AxisRange AutoRange(const std::vector<double>& values, bool allow_log, double margin = 0.05,
                    double decades_for_log = 3.0, double max_decades = 8.0);

// The y range raised so that no point (x, y) lies under a legend in the top-right corner of the
// plot area, `width` x `height` as fractions of the area: the points in the corner's x band must
// stay below the corner, so y.max grows (in log10 when y.log) to put the highest of them just under
// it (the x band in log10 when x.log). The minimum and every other point stay where they were;
// nothing is clipped.
// Tick values for a logarithmic axis over [lo, hi] (0 < lo < hi): the powers of ten inside, with
// 2 and 5 times them as well when fewer than three powers fall inside, and 1..9 times them when
// the range is within one decade (still at least two ticks when the range allows).
std::vector<double> LogTicks(double lo, double hi);

AxisRange MakeRoomForLegend(const AxisRange& y, const AxisRange& x, const std::vector<double>& xs,
                            const std::vector<double>& ys, double width, double height);

}  // namespace gearnvh::render
