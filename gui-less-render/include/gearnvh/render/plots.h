// Plots rendered offscreen with VTK's chart module into PNG files (docs/design.md §7).
//
// The figures are plain data (titles, axis labels with units, series, labels); this library only
// draws them. Every render first makes sure an X display exists (display.h) and reports a missing
// one as a status, never a crash. PNGs are written to a temporary file and renamed, so a reader
// never sees half an image; the image is encoded in memory and written by this library, so a
// failed write (a full disk) is a status with the system's reason, never VTK's or libpng's text on
// stderr (VTK's warning output is off). Rendering is serialised process-wide (one GL context at a
// time); the callers compute in parallel and draw one after another.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/render/layout.h"

namespace gearnvh::render {

using Rgb = std::array<double, 3>;  // 0..1

// The default palette (colour-blind safe, Okabe–Ito), cycled by series index.
Rgb PaletteColor(int index);

struct ImageOptions {
  int width = 1200;       // px, >= 200
  int height = 800;       // px, >= 150
  double dpi = 100;       // scales fonts (points at dpi / 72 px); >= 36
  void Validate() const;  // throws std::invalid_argument naming the field
};

struct Series {
  enum class Style { kLine, kDashed, kPoints };
  std::string label;  // legend entry; empty: not in the legend
  std::vector<double> x, y;
  Style style = Style::kLine;
  enum class Marker { kCircle, kDiamond };  // of kPoints
  Marker marker = Marker::kCircle;
  int color = -1;      // palette index; -1: the series index
  double width = 2.0;  // line width or marker size, px
};

struct TextLabel {
  double x = 0.0, y = 0.0;  // data coordinates
  std::string text;
};

struct LinePlot {
  std::string title, x_label, y_label;  // labels carry their units, e.g. "speed (rpm)"
  std::vector<Series> series;
  std::vector<TextLabel> labels;
  bool log_x = false;      // logarithmic x axis (non-positive x are not drawn)
  bool log_y = false;      // logarithmic y axis
  bool auto_log_y = true;  // also logarithmic when the data are positive over >= 3 decades
  // Use the ranges below instead of the data's range (with a margin, layout.h AutoRange).
  bool fixed_x = false, fixed_y = false;
  double x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
  bool legend = true;
};

// values[iy * nx + ix] at the cell centres of a regular grid spanning [x_min, x_max] x
// [y_min, y_max] (cell edges). Colour: a sequential map, or a diverging map centred at 0.
// A log axis (x_min > 0) spaces the cells evenly in log10 (a geometric grid) and labels its ticks
// with the values.
struct HeatMap {
  std::string title, x_label, y_label;
  std::string value_label;  // what the colours mean; shown in the title as "(colour: ...)"
  int nx = 0, ny = 0;
  double x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
  bool log_x = false, log_y = false;
  std::vector<double> values;  // NaN: no value (drawn grey)
  bool diverging = false;
};

// Where a drawing put its text, in pixels of the image (origin bottom left, y up, as VTK's scene).
// The boxes in `text` (the title, the legend, the data labels drawn) overlap no other and lie
// inside `image`, and no label overlaps `data_marks`; the tests check this on every figure.
struct DrawnLayout {
  Box image, plot_area;
  Box title;                    // empty box (all 0) when there is no title
  std::optional<Box> legend;    // the series legend or the colour bar
  std::vector<Box> labels;      // the data labels that were drawn
  std::vector<Box> data_marks;  // point markers and samples along the drawn lines (line plots)
  int labels_dropped = 0;       // data labels with no free place (left out)
  std::vector<Box> text;        // title, legend and labels together
};

struct RenderStatus {
  bool ok = true;
  std::string message;
  DrawnLayout layout;    // when ok
  int error_number = 0;  // the system's errno when the PNG file could not be written (ENOSPC)
};

RenderStatus RenderLinePlot(const LinePlot& plot, const ImageOptions& options,
                            const std::string& png_path);
RenderStatus RenderHeatMap(const HeatMap& map, const ImageOptions& options,
                           const std::string& png_path);

// A PNG read back (tests, report checks): RGB rows from the top.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 3 bytes per pixel
  std::array<std::uint8_t, 3> Pixel(int x, int y) const;
  // Pixels in [x0, x1) x [y0, y1) (fractions of the size, from the top left) that differ from
  // `background` by more than `tolerance` in any channel.
  long CountDifferent(double x0, double y0, double x1, double y1,
                      const std::array<std::uint8_t, 3>& background, int tolerance = 24) const;
};
// Throws std::runtime_error when the file is not a readable PNG.
RgbImage ReadPng(const std::string& path);

}  // namespace gearnvh::render
