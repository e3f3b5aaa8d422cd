// Plot layout as geometry: labels never overlap each other, the legend or markers, stay inside the
// plot area; axis ranges come from the data with a margin, logarithmic when it spans decades.
#include "gearnvh/render/layout.h"

#include <catch2/catch.hpp>
#include <cmath>

namespace gearnvh::render {
namespace {

TEST_CASE("labels: crowded points get non-overlapping labels inside the area", "[layout]") {
  const Box area{0, 0, 800, 600};
  const Box legend{600, 500, 800, 600};
  std::vector<LabelRequest> labels;
  std::vector<Box> markers;
  // Twelve critical speeds within a few pixels of each other, some under the legend.
  for (int i = 0; i < 12; ++i) {
    const double x = 550.0 + 10.0 * i, y = 480.0 + 3.0 * i;
    labels.push_back({x, y, 70.0, 16.0});
    markers.push_back({x - 3, y - 3, x + 3, y + 3});
  }
  std::vector<Box> obstacles = markers;
  obstacles.push_back(legend);
  const auto placed = PlaceLabels(labels, area, obstacles);
  REQUIRE(placed.size() == labels.size());
  int shown = 0;
  for (size_t i = 0; i < placed.size(); ++i) {
    if (!placed[i]) continue;
    ++shown;
    const Box& b = *placed[i];
    CHECK(b.Inside(area));
    CHECK_FALSE(b.Overlaps(legend));
    for (const Box& m : markers) CHECK_FALSE(b.Overlaps(m));
    for (size_t j = 0; j < i; ++j) {
      if (placed[j]) CHECK_FALSE(b.Overlaps(*placed[j]));
    }
    CHECK(b.x1 - b.x0 == 70.0);
  }
  CHECK(shown >= 2);  // room around the cluster for several
  CHECK(placed[0]);   // the first (most important) always finds room here
  CHECK(shown < 12);  // and not all twelve fit: the rest are dropped, not stacked
}

TEST_CASE("labels: a lone label sits right-above its point", "[layout]") {
  const auto placed = PlaceLabels({{100, 100, 50, 10}}, {0, 0, 400, 300}, {});
  REQUIRE(placed[0]);
  CHECK(placed[0]->x0 == 104.0);
  CHECK(placed[0]->y0 == 104.0);
  // At the right edge it moves to the left of its point.
  const auto edge = PlaceLabels({{390, 100, 50, 10}}, {0, 0, 400, 300}, {});
  REQUIRE(edge[0]);
  CHECK(edge[0]->x1 == 386.0);
}

TEST_CASE("axis ranges: linear with a margin, logarithmic over decades", "[layout]") {
  // Exact arithmetic on small binary fractions: equality up to 1e-12.
  const AxisRange lin = AutoRange({2.0, 4.0, 3.0, NAN}, true);
  CHECK_FALSE(lin.log);
  CHECK(lin.min == Approx(1.9).epsilon(1e-12));
  CHECK(lin.max == Approx(4.1).epsilon(1e-12));
  const AxisRange decades = AutoRange({1e-9, 1e-6, 3e-5}, true);
  CHECK(decades.log);
  const double pad = std::pow(3e-5 / 1e-9, 0.05);
  CHECK(decades.min == Approx(1e-9 / pad).epsilon(1e-12));
  CHECK(decades.max == Approx(3e-5 * pad).epsilon(1e-12));
  // Rounding noise far below is cut at 8 decades under the maximum.
  const AxisRange noisy = AutoRange({1e-30, 1e-6, 1.0}, true);
  CHECK(noisy.log);
  CHECK(noisy.min == Approx(1e-8 / std::pow(1e8, 0.05)).epsilon(1e-12));
  CHECK_FALSE(AutoRange({1e-9, 1e-6, 3e-5}, false).log);  // not allowed
  CHECK_FALSE(AutoRange({-1e-9, 1e-6, 3e-5}, true).log);  // a non-positive value
  CHECK_FALSE(AutoRange({1.0, 999.0}, true).log);         // under three decades
  const AxisRange flat = AutoRange({5.0, 5.0}, true);
  CHECK(flat.min == Approx(4.5).epsilon(1e-12));
  CHECK(flat.max == Approx(5.5).epsilon(1e-12));
  const AxisRange none = AutoRange({}, true);
  CHECK(none.min == 0.0);
  CHECK(none.max == 1.0);
}

}  // namespace
}  // namespace gearnvh::render

namespace gearnvh::render {
namespace {

TEST_CASE("legend room: data under the legend's corner raise the y range, others do not",
          "[layout]") {
  const AxisRange x{0.0, 10.0, false};
  const AxisRange y{0.0, 100.0, false};
  // A point at the top right (x = 9.5, y = 95) sits under a legend 30 % wide, 20 % high.
  const AxisRange raised = MakeRoomForLegend(y, x, {1.0, 9.5}, {50.0, 95.0}, 0.3, 0.2);
  CHECK(raised.min == 0.0);
  // Afterwards the point is below the corner: 95 < max - 0.2 (max - min).
  CHECK(95.0 < raised.max - 0.2 * (raised.max - raised.min));
  CHECK(raised.max == Approx(1.02 * 95.0 / 0.8).epsilon(1e-12));
  // High data outside the corner's x band, or low data inside it, leave the range alone.
  CHECK(MakeRoomForLegend(y, x, {1.0, 9.5}, {99.0, 10.0}, 0.3, 0.2).max == 100.0);
  // Log axes work in decades.
  const AxisRange ylog{1e-6, 1.0, true};
  const AxisRange r = MakeRoomForLegend(ylog, x, {9.9}, {0.5}, 0.3, 0.25);
  CHECK(r.log);
  CHECK(std::log10(0.5) < std::log10(r.max) - 0.25 * (std::log10(r.max) + 6.0));
}

TEST_CASE("log ticks: decades, with 2 and 5 on short ranges, exact decimal values", "[layout]") {
  // Four decades: the powers of ten only.
  CHECK(LogTicks(0.5, 2000.0) == std::vector<double>{1.0, 10.0, 100.0, 1000.0});
  // 0.05..5 N m holds two powers of ten: 2 and 5 times them join (values as printed, 0.2 not
  // 0.20000000000000001: they are rounded to 12 digits).
  CHECK(LogTicks(0.05, 5.0) == std::vector<double>{0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 5.0});
  // Within one decade: 1..9 times the power.
  CHECK(LogTicks(600.0, 900.0) == std::vector<double>{600.0, 700.0, 800.0, 900.0});
  CHECK(LogTicks(0.0, 1.0).empty());
}

}  // namespace
}  // namespace gearnvh::render
