// Offscreen VTK plots: real PNGs of the requested size with ink where the plot should be.
#include "gearnvh/render/plots.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "gearnvh/render/display.h"
#include "support/figure_checks.h"
#include "support/run_command.h"

namespace gearnvh {
namespace {

using render::ReadPng;

const std::array<std::uint8_t, 3> kWhite{255, 255, 255};

TEST_CASE("render: a display is available (DISPLAY or a private Xvfb)", "[render]") {
  const render::DisplayStatus& d = render::EnsureDisplay();
  INFO(d.message);
  REQUIRE(d.ok());
  CHECK(!d.display.empty());
}

TEST_CASE("render: a line plot has its size, a title, and coloured curves inside the axes",
          "[render]") {
  const testing::TempDir dir;
  render::LinePlot plot;
  plot.title = "Campbell diagram";
  plot.x_label = "speed (rpm)";
  plot.y_label = "frequency (Hz)";
  render::Series a{"mode 1", {}, {}};
  render::Series b{"1x mesh", {}, {}, render::Series::Style::kDashed};
  for (int i = 0; i <= 50; ++i) {
    a.x.push_back(100.0 * i);
    a.y.push_back(1000.0 + 2.0 * i);
    b.x.push_back(100.0 * i);
    b.y.push_back(0.45 * 100.0 * i);
  }
  plot.series = {a, b};
  plot.labels = {{2222.0, 1000.0, "critical 2222 rpm"}};
  render::ImageOptions options;
  options.width = 900;
  options.height = 600;
  const std::string path = (dir.path() / "campbell.png").string();
  const render::RenderStatus s = render::RenderLinePlot(plot, options, path);
  INFO(s.message);
  REQUIRE(s.ok);
  const render::RgbImage img = ReadPng(path);
  CHECK(img.width == 900);
  CHECK(img.height == 600);
  // Title text in the top band; curves (blue mode 1, orange order line) inside the plot area.
  CHECK(img.CountDifferent(0.3, 0.0, 0.7, 0.1, kWhite) > 100);
  CHECK(img.CountDifferent(0.15, 0.15, 0.85, 0.85, kWhite) > 1000);
  long blue = 0, orange = 0;
  for (int y = img.height / 10; y < 9 * img.height / 10; ++y) {
    for (int x = img.width / 10; x < 9 * img.width / 10; ++x) {
      const auto p = img.Pixel(x, y);
      if (p[2] > 140 && p[0] < 60) ++blue;
      if (p[0] > 200 && p[1] > 120 && p[1] < 190 && p[2] < 60) ++orange;
    }
  }
  CHECK(blue > 200);
  CHECK(orange > 100);
  // No temporary files left beside the image.
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  CHECK(files == 1);
}

TEST_CASE("render: a heat map fills the plot area with its colour map", "[render]") {
  const testing::TempDir dir;
  render::HeatMap map;
  map.title = "Lyapunov exponent";
  map.x_label = "speed (rpm)";
  map.y_label = "drag torque (N m)";
  map.value_label = "1/forcing cycle";
  map.nx = 8;
  map.ny = 6;
  map.x_min = 600;
  map.x_max = 3000;
  map.y_min = 0.05;
  map.y_max = 5;
  map.diverging = true;
  for (int iy = 0; iy < map.ny; ++iy)
    for (int ix = 0; ix < map.nx; ++ix) map.values.push_back(iy < 3 ? 4.0 : -8.0 + ix);
  const std::string path = (dir.path() / "atlas.png").string();
  const render::RenderStatus s = render::RenderHeatMap(map, {}, path);
  INFO(s.message);
  REQUIRE(s.ok);
  const render::RgbImage img = ReadPng(path);
  CHECK(img.width == 1200);
  CHECK(img.height == 800);
  // Most of the plot area is coloured (cells), not background.
  const long inside = img.CountDifferent(0.2, 0.2, 0.7, 0.8, kWhite);
  CHECK(inside > 0.6 * (0.5 * 1200) * (0.6 * 800));
  // Bottom rows (positive exponent) red; top rows (negative) blue.
  long red = 0, blue = 0;
  for (int y = static_cast<int>(0.2 * img.height); y < static_cast<int>(0.8 * img.height); ++y) {
    for (int x = static_cast<int>(0.2 * img.width); x < static_cast<int>(0.7 * img.width); ++x) {
      const auto p = img.Pixel(x, y);
      if (p[0] > 120 && p[2] < 90) ++red;
      if (p[2] > 100 && p[0] < 90) ++blue;
    }
  }
  CHECK(red > 10000);
  CHECK(blue > 10000);
}

// A crowded figure: a long title, a legend and twenty labels on points a few pixels apart.
render::LinePlot CrowdedPlot() {
  render::LinePlot plot;
  plot.title = "Dynamic transmission error spectrum with mesh harmonics and sidebands (crowded)";
  plot.x_label = "frequency (Hz)";
  plot.y_label = "TE amplitude (µm)";
  render::Series line{"TE spectrum", {}, {}};
  render::Series marks{"sidebands", {}, {}, render::Series::Style::kPoints};
  marks.width = 8.0;
  for (int i = 1; i <= 400; ++i) {
    line.x.push_back(5.0 * i);
    line.y.push_back(1e-3 + std::exp(-std::pow((5.0 * i - 1000.0) / 40.0, 2)));
  }
  for (int k = 0; k < 20; ++k) {
    const double f = 900.0 + 10.0 * k;
    marks.x.push_back(f);
    marks.y.push_back(1e-3 + std::exp(-std::pow((f - 1000.0) / 40.0, 2)));
    plot.labels.push_back({f, marks.y.back(), "1x mesh +" + std::to_string(k) + "x pinion"});
  }
  plot.series = {line, marks};
  return plot;
}

TEST_CASE("render: labels, legend and title never overlap and stay inside, at 1200x800 and 600x400",
          "[render]") {
  const testing::TempDir dir;
  for (const auto& [w, h] : {std::pair{1200, 800}, std::pair{600, 400}}) {
    render::ImageOptions options;
    options.width = w;
    options.height = h;
    const std::string path = (dir.path() / ("crowded" + std::to_string(w) + ".png")).string();
    const render::RenderStatus s = render::RenderLinePlot(CrowdedPlot(), options, path);
    testing::CheckDrawnFigure(s, path, w, h);
    // Every label is drawn apart or left out (never overprinted); the title fits.
    CHECK(s.layout.labels.size() >= 10);
    CHECK(s.layout.labels.size() + s.layout.labels_dropped == 20);
    CHECK(s.layout.title.x1 - s.layout.title.x0 > 0.3 * w);
    REQUIRE(s.layout.legend.has_value());
  }
}

TEST_CASE("render: a log x axis shows decades of cost, with labels placed", "[render]") {
  const testing::TempDir dir;
  render::LinePlot plot;
  plot.title = "Modal tiers: accuracy against cost";
  plot.x_label = "cost (µs per mesh cycle)";
  plot.y_label = "largest frequency error (%)";
  plot.log_x = plot.log_y = true;
  render::Series points{
      "", {0.5, 3.0, 40.0, 900.0}, {20.0, 2.0, 0.1, 1e-6}, render::Series::Style::kPoints};
  points.width = 10.0;
  plot.series = {points};
  for (size_t i = 0; i < points.x.size(); ++i) {
    plot.labels.push_back({points.x[i], points.y[i], "N" + std::to_string(4 * (i + 1))});
  }
  render::ImageOptions options;
  options.width = 600;
  options.height = 400;
  const std::string path = (dir.path() / "tiers.png").string();
  const render::RenderStatus s = render::RenderLinePlot(plot, options, path);
  testing::CheckDrawnFigure(s, path, 600, 400, 100);
  // Four points a decade or more apart: every label finds a place.
  CHECK(s.layout.labels.size() == 4);
  CHECK(s.layout.labels_dropped == 0);
}

TEST_CASE("render: a heat map on log axes fills the plot area, its text inside and apart",
          "[render]") {
  const testing::TempDir dir;
  render::HeatMap map;
  map.title = "Chaos atlas: rattle index";
  map.x_label = "pinion speed (rpm)";
  map.y_label = "drag torque (N m)";
  map.value_label = "log10 J";
  map.nx = 6;
  map.ny = 5;
  map.x_min = 600;
  map.x_max = 6000;
  map.y_min = 0.05;
  map.y_max = 5;
  map.log_x = map.log_y = true;
  for (int i = 0; i < map.nx * map.ny; ++i) map.values.push_back(std::sin(0.7 * i));
  for (const auto& [w, h] : {std::pair{1200, 800}, std::pair{600, 400}}) {
    render::ImageOptions options;
    options.width = w;
    options.height = h;
    const std::string path = (dir.path() / ("atlas" + std::to_string(w) + ".png")).string();
    const render::RenderStatus s = render::RenderHeatMap(map, options, path);
    // Cells cover the plot area: at least half of it is coloured.
    const double area = (s.layout.plot_area.x1 - s.layout.plot_area.x0) *
                        (s.layout.plot_area.y1 - s.layout.plot_area.y0);
    testing::CheckDrawnFigure(s, path, w, h, static_cast<long>(0.5 * area));
  }
}

}  // namespace
}  // namespace gearnvh
