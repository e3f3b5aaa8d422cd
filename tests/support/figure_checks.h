// Checks on a drawn figure (render::RenderStatus and its PNG): the text boxes the drawing reports
// overlap no other and lie inside the image, no data label covers a marker or a line, the plot area
// lies inside the image, and there is ink inside the plot area. With GEARNVH_KEEP_FIGURES=DIR set,
// the PNG is also copied into DIR (to look at what the tests drew).
#pragma once

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "gearnvh/render/plots.h"

namespace gearnvh::testing {

inline void CheckDrawnFigure(const render::RenderStatus& status, const std::string& png, int width,
                             int height, long min_ink = 500) {
  INFO(png << ": " << status.message);
  REQUIRE(status.ok);
  if (const char* keep = std::getenv("GEARNVH_KEEP_FIGURES"); keep != nullptr) {
    std::error_code ec;
    std::filesystem::create_directories(keep, ec);
    std::filesystem::copy_file(png,
                               std::filesystem::path(keep) / std::filesystem::path(png).filename(),
                               std::filesystem::copy_options::overwrite_existing, ec);
  }
  const render::DrawnLayout& l = status.layout;
  CHECK(l.image.x1 == Approx(width));
  CHECK(l.image.y1 == Approx(height));
  // A plot area of real size, inside the image.
  CHECK(l.plot_area.Inside(l.image));
  CHECK(l.plot_area.x1 - l.plot_area.x0 > 0.4 * width);
  CHECK(l.plot_area.y1 - l.plot_area.y0 > 0.4 * height);
  REQUIRE(!l.text.empty());  // at least the title
  for (size_t i = 0; i < l.text.size(); ++i) {
    const render::Box& a = l.text[i];
    INFO("text box " << i << ": " << a.x0 << " " << a.y0 << " " << a.x1 << " " << a.y1);
    CHECK(a.x1 > a.x0);
    CHECK(a.Inside(l.image));
    for (size_t j = i + 1; j < l.text.size(); ++j) CHECK_FALSE(a.Overlaps(l.text[j]));
  }
  long covered = 0;
  for (const render::Box& b : l.labels) {
    CHECK(b.Inside(l.plot_area));
    for (const render::Box& d : l.data_marks) covered += b.Overlaps(d) ? 1 : 0;
  }
  CHECK(covered == 0);
  // Ink inside the plot area (the layout's y runs up, the image's rows down); the white
  // background differs from every palette colour by more than the tolerance.
  const render::RgbImage img = render::ReadPng(png);
  REQUIRE(img.width == width);
  REQUIRE(img.height == height);
  const double x0 = l.plot_area.x0 / width, x1 = l.plot_area.x1 / width;
  const double y0 = 1.0 - l.plot_area.y1 / height, y1 = 1.0 - l.plot_area.y0 / height;
  CHECK(img.CountDifferent(x0 + 0.01, y0 + 0.01, x1 - 0.01, y1 - 0.01, {255, 255, 255}) >= min_ink);
}

}  // namespace gearnvh::testing
