// Offscreen VTK plots: real PNGs of the requested size with ink where the plot should be.
#include "gearnvh/render/plots.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>

#include "gearnvh/render/display.h"
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

}  // namespace
}  // namespace gearnvh
