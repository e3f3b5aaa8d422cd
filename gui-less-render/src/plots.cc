#include "gearnvh/render/plots.h"

#include <unistd.h>
#include <vtkAxis.h>
#include <vtkChartHistogram2D.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkColorLegend.h>
#include <vtkColorTransferFunction.h>
#include <vtkContext2D.h>
#include <vtkContextItem.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkPointData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <set>
#include <stdexcept>
#include <utility>

#include "chart_items.h"
#include "gearnvh/render/display.h"
#include "gearnvh/render/layout.h"
#include "png_file.h"

namespace gearnvh::render {

namespace {

std::mutex g_render_mutex;

void StyleAxis(vtkAxis* axis, const std::string& title) {
  axis->SetTitle(title);
  axis->GetTitleProperties()->SetFontSize(16);
  axis->GetTitleProperties()->SetBold(false);
  axis->GetLabelProperties()->SetFontSize(13);
  axis->SetGridVisible(true);
}

// Renders the view into png_path atomically.
RenderStatus WriteView(vtkContextView* view, const ImageOptions& options,
                       const std::string& png_path) {
  vtkRenderWindow* window = view->GetRenderWindow();
  window->SetOffScreenRendering(1);
  window->SetSize(options.width, options.height);
  window->SetDPI(static_cast<int>(options.dpi));
  view->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  window->Render();
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->Update();
  vtkNew<vtkPNGWriter> writer;
  writer->WriteToMemoryOn();
  writer->SetInputConnection(grab->GetOutputPort());
  writer->Write();
  vtkUnsignedCharArray* png = writer->GetResult();
  if (writer->GetErrorCode() != 0 || png == nullptr || png->GetNumberOfValues() == 0) {
    return {false, "could not encode " + png_path, {}};
  }
  return WritePng(png_path, png->GetPointer(0), static_cast<size_t>(png->GetNumberOfValues()));
}

RenderStatus CheckDisplay() {
  // VTK's warnings and errors would go to stderr in colour, between the command's own lines:
  // every failure that matters comes back as a status.
  static std::once_flag quiet;
  std::call_once(quiet, [] { vtkObject::GlobalWarningDisplayOff(); });
  const DisplayStatus& d = EnsureDisplay();
  if (!d.ok()) return {false, d.message, {}};
  return {};
}

}  // namespace

Rgb PaletteColor(int index) {
  static const Rgb palette[] = {{0.00, 0.45, 0.70}, {0.90, 0.62, 0.00}, {0.00, 0.62, 0.45},
                                {0.80, 0.40, 0.00}, {0.34, 0.71, 0.91}, {0.80, 0.47, 0.65},
                                {0.35, 0.35, 0.35}, {0.94, 0.89, 0.26}};
  const int n = static_cast<int>(sizeof(palette) / sizeof(palette[0]));
  return palette[((index % n) + n) % n];
}

void ImageOptions::Validate() const {
  if (width < 200) throw std::invalid_argument("image width must be >= 200 px");
  if (height < 150) throw std::invalid_argument("image height must be >= 150 px");
  if (!(dpi >= 36)) throw std::invalid_argument("image dpi must be >= 36");
}

RenderStatus RenderLinePlot(const LinePlot& plot, const ImageOptions& options,
                            const std::string& png_path) {
  options.Validate();
  if (RenderStatus s = CheckDisplay(); !s.ok) return s;
  const std::lock_guard<std::mutex> lock(g_render_mutex);
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartXY> chart;
  DrawnLayout layout;
  ChartText text;
  AddChartWithLayout(view, chart, plot.title, &text, &layout);
  StyleAxis(chart->GetAxis(vtkAxis::BOTTOM), plot.x_label);
  StyleAxis(chart->GetAxis(vtkAxis::LEFT), plot.y_label);
  // Ranges: as given, or from the data with a margin (logarithmic in y when asked for, or when
  // the data are positive and span three decades or more).
  std::vector<double> all_x, all_y;
  for (const Series& s : plot.series) {
    all_x.insert(all_x.end(), s.x.begin(), s.x.end());
    all_y.insert(all_y.end(), s.y.begin(), s.y.end());
  }
  vtkAxis* x_axis = chart->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* y_axis = chart->GetAxis(vtkAxis::LEFT);
  std::vector<double> shown_x;  // a log x axis shows the positive x only
  for (double v : all_x) {
    if (!plot.log_x || v > 0.0) shown_x.push_back(v);
  }
  const AxisRange x_range = plot.fixed_x ? AxisRange{plot.x_min, plot.x_max, plot.log_x}
                                         : AutoRange(shown_x, plot.log_x, 0.02, 0.0);
  AxisRange y_range = plot.fixed_y ? AxisRange{plot.y_min, plot.y_max, plot.log_y}
                                   : AutoRange(all_y, plot.log_y || plot.auto_log_y);
  if (plot.log_y && !y_range.log) {
    // Asked for log but the data have non-positive values: show the positive ones.
    std::vector<double> positive;
    for (double v : all_y) {
      if (v > 0.0) positive.push_back(v);
    }
    y_range = AutoRange(positive, true, 0.05, 0.0);
  }
  const bool log_y = plot.log_y || y_range.log;
  y_range.log = log_y;
  // The legend (top right) must not hide data: estimate its box from its entries and the font
  // (13 pt labels, one line each, a 10 px frame) against the plot area (the image less about
  // 110 x 120 px of titles and tick labels), and raise the y range until the data clear it.
  // A legend of more than three entries goes outside, right of the plot area; a smaller one sits
  // inside, top right.
  int legend_entries = 0;
  for (const Series& s : plot.series) legend_entries += s.label.empty() || s.x.empty() ? 0 : 1;
  const bool legend_inside = legend_entries <= 3;
  if (plot.legend && legend_inside) {
    int entries = 0;
    size_t longest = 0;
    for (const Series& s : plot.series) {
      if (s.label.empty() || s.x.empty()) continue;
      ++entries;
      longest = std::max(longest, s.label.size());
    }
    if (entries > 0) {
      const double font_px = 13.0 * options.dpi / 72.0;
      const double box_w = 0.55 * font_px * static_cast<double>(longest) + 45.0;
      const double box_h = 1.35 * font_px * entries + 10.0;
      const double area_w = std::max(1.0, options.width - 110.0);
      const double area_h = std::max(1.0, options.height - 120.0);
      y_range = MakeRoomForLegend(y_range, x_range, all_x, all_y, std::min(0.9, box_w / area_w),
                                  std::min(0.7, box_h / area_h));
    }
  }
  if (log_y) y_axis->SetLogScale(true);
  if (x_range.log) x_axis->SetLogScale(true);
  x_axis->SetUnscaledRange(x_range.min, x_range.max);
  x_axis->SetBehavior(vtkAxis::FIXED);
  y_axis->SetUnscaledRange(y_range.min, y_range.max);
  y_axis->SetBehavior(vtkAxis::FIXED);
  bool any_label = false;
  for (size_t i = 0; i < plot.series.size(); ++i) {
    const Series& s = plot.series[i];
    if (s.x.size() != s.y.size()) {
      throw std::invalid_argument("series '" + s.label + "': x and y differ in length");
    }
    if (s.x.empty()) continue;
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> xs, ys;
    xs->SetName("x");
    ys->SetName(s.label.empty() ? ("series " + std::to_string(i)).c_str() : s.label.c_str());
    for (size_t k = 0; k < s.x.size(); ++k) {
      // Log axes cannot show non-positive values; NaN breaks are drawn as gaps by VTK.
      const bool hidden = (log_y && !(s.y[k] > 0.0)) || (x_range.log && !(s.x[k] > 0.0));
      const double y = hidden ? std::numeric_limits<double>::quiet_NaN() : s.y[k];
      xs->InsertNextValue(s.x[k]);
      ys->InsertNextValue(y);
    }
    table->AddColumn(xs);
    table->AddColumn(ys);
    vtkPlot* p =
        chart->AddPlot(s.style == Series::Style::kPoints ? vtkChart::POINTS : vtkChart::LINE);
    p->SetInputData(table, 0, 1);
    const Rgb c = PaletteColor(s.color >= 0 ? s.color : static_cast<int>(i));
    p->SetColor(static_cast<unsigned char>(255 * c[0]), static_cast<unsigned char>(255 * c[1]),
                static_cast<unsigned char>(255 * c[2]), 255);
    p->SetWidth(static_cast<float>(s.width));
    if (s.style == Series::Style::kDashed) p->GetPen()->SetLineType(vtkPen::DASH_LINE);
    if (s.style == Series::Style::kPoints) {
      auto* points = vtkPlotPoints::SafeDownCast(p);
      if (points != nullptr) {
        points->SetMarkerStyle(s.marker == Series::Marker::kDiamond ? vtkPlotPoints::DIAMOND
                                                                    : vtkPlotPoints::CIRCLE);
        points->SetMarkerSize(static_cast<float>(s.width));
      }
    }
    p->SetLabel(s.label);
    if (s.label.empty()) {
      p->SetLegendVisibility(false);
    } else {
      any_label = true;
    }
  }
  chart->SetShowLegend(plot.legend && any_label);
  chart->GetLegend()->SetLabelSize(13);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  chart->GetLegend()->SetInline(legend_inside);
  text.labels = plot.labels;
  for (const Series& s : plot.series) {
    if (s.style != Series::Style::kPoints) {
      text.lines.push_back({&s.x, &s.y, s.width});
      continue;
    }
    for (size_t k = 0; k < s.x.size(); ++k) text.markers.push_back({s.x[k], s.y[k], s.width});
  }
  RenderStatus status = WriteView(view, options, png_path);
  if (status.ok) status.layout = layout;
  return status;
}

RenderStatus RenderHeatMap(const HeatMap& map, const ImageOptions& options,
                           const std::string& png_path) {
  options.Validate();
  if (map.nx < 1 || map.ny < 1 || static_cast<int>(map.values.size()) != map.nx * map.ny) {
    throw std::invalid_argument("heat map '" + map.title + "': values must be nx * ny");
  }
  if (RenderStatus s = CheckDisplay(); !s.ok) return s;
  const std::lock_guard<std::mutex> lock(g_render_mutex);
  vtkNew<vtkImageData> image;
  image->SetDimensions(map.nx, map.ny, 1);
  if ((map.log_x && !(map.x_min > 0.0)) || (map.log_y && !(map.y_min > 0.0))) {
    throw std::invalid_argument("heat map '" + map.title + "': a log axis needs a positive range");
  }
  // A log axis is drawn in log10 units (the cells of a geometric grid are then even) with ticks
  // labelled in the values.
  const double x_lo = map.log_x ? std::log10(map.x_min) : map.x_min;
  const double x_hi = map.log_x ? std::log10(map.x_max) : map.x_max;
  const double y_lo = map.log_y ? std::log10(map.y_min) : map.y_min;
  const double y_hi = map.log_y ? std::log10(map.y_max) : map.y_max;
  const double dx = (x_hi - x_lo) / map.nx, dy = (y_hi - y_lo) / map.ny;
  image->SetOrigin(x_lo, y_lo, 0.0);
  image->SetSpacing(dx, dy, 1.0);
  image->AllocateScalars(VTK_DOUBLE, 1);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int iy = 0; iy < map.ny; ++iy) {
    for (int ix = 0; ix < map.nx; ++ix) {
      const double v = map.values[static_cast<size_t>(iy * map.nx + ix)];
      *static_cast<double*>(image->GetScalarPointer(ix, iy, 0)) = v;
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    }
  }
  if (!std::isfinite(lo)) lo = 0.0, hi = 1.0;
  if (hi <= lo) hi = lo + 1.0;
  vtkNew<vtkColorTransferFunction> colors;
  colors->SetNanColor(0.75, 0.75, 0.75);
  if (map.diverging) {
    const double m = std::max(std::abs(lo), std::abs(hi));
    colors->AddRGBPoint(-m, 0.02, 0.19, 0.38);
    colors->AddRGBPoint(-0.5 * m, 0.26, 0.58, 0.76);
    colors->AddRGBPoint(0.0, 0.97, 0.97, 0.97);
    colors->AddRGBPoint(0.5 * m, 0.84, 0.38, 0.30);
    colors->AddRGBPoint(m, 0.40, 0.0, 0.05);
  } else {  // viridis, five stops
    const double stops[5][3] = {{0.267, 0.005, 0.329},
                                {0.231, 0.322, 0.545},
                                {0.129, 0.569, 0.549},
                                {0.369, 0.788, 0.384},
                                {0.993, 0.906, 0.144}};
    for (int k = 0; k < 5; ++k) {
      colors->AddRGBPoint(lo + (hi - lo) * k / 4.0, stops[k][0], stops[k][1], stops[k][2]);
    }
  }
  vtkNew<vtkContextView> view;
  vtkNew<vtkChartHistogram2D> chart;
  DrawnLayout layout;
  const ChartText no_text;
  // The colour bar's own title overprints its tick labels (VTK 9.1): the value label goes into
  // the figure's title instead.
  AddChartWithLayout(
      view, chart,
      map.value_label.empty() ? map.title : map.title + " (colour: " + map.value_label + ")",
      &no_text, &layout);
  chart->SetInputData(image);
  chart->SetTransferFunction(colors);
  StyleAxis(chart->GetAxis(vtkAxis::BOTTOM), map.x_label);
  StyleAxis(chart->GetAxis(vtkAxis::LEFT), map.y_label);
  chart->GetAxis(vtkAxis::BOTTOM)->SetGridVisible(false);
  chart->GetAxis(vtkAxis::LEFT)->SetGridVisible(false);
  chart->GetAxis(vtkAxis::BOTTOM)->SetRange(x_lo, x_hi);
  chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  chart->GetAxis(vtkAxis::LEFT)->SetRange(y_lo, y_hi);
  chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  if (map.log_x) SetLogTicks(chart->GetAxis(vtkAxis::BOTTOM), map.x_min, map.x_max);
  if (map.log_y) SetLogTicks(chart->GetAxis(vtkAxis::LEFT), map.y_min, map.y_max);
  if (auto* legend = vtkColorLegend::SafeDownCast(chart->GetLegend()); legend != nullptr) {
    legend->SetLabelSize(13);
  }
  RenderStatus status = WriteView(view, options, png_path);
  if (status.ok) status.layout = layout;
  return status;
}

std::array<std::uint8_t, 3> RgbImage::Pixel(int x, int y) const {
  const size_t i =
      3 * (static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x));
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

long RgbImage::CountDifferent(double x0, double y0, double x1, double y1,
                              const std::array<std::uint8_t, 3>& background, int tolerance) const {
  long count = 0;
  const int xa = static_cast<int>(x0 * width), xb = static_cast<int>(x1 * width);
  const int ya = static_cast<int>(y0 * height), yb = static_cast<int>(y1 * height);
  for (int y = std::max(0, ya); y < std::min(height, yb); ++y) {
    for (int x = std::max(0, xa); x < std::min(width, xb); ++x) {
      const auto p = Pixel(x, y);
      for (int c = 0; c < 3; ++c) {
        if (std::abs(static_cast<int>(p[c]) - static_cast<int>(background[c])) > tolerance) {
          ++count;
          break;
        }
      }
    }
  }
  return count;
}

RgbImage ReadPng(const std::string& path) {
  vtkNew<vtkPNGReader> reader;
  if (reader->CanReadFile(path.c_str()) == 0) throw std::runtime_error("not a PNG: " + path);
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  RgbImage out;
  out.width = dims[0];
  out.height = dims[1];
  const int components = data->GetNumberOfScalarComponents();
  out.rgb.resize(3 * static_cast<size_t>(out.width) * static_cast<size_t>(out.height));
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      // VTK's rows run bottom-up; RgbImage rows run top-down.
      const auto* p =
          static_cast<const unsigned char*>(data->GetScalarPointer(x, out.height - 1 - y, 0));
      for (int c = 0; c < 3; ++c) {
        out.rgb[3 * (static_cast<size_t>(y) * out.width + x) + c] = p[std::min(c, components - 1)];
      }
    }
  }
  return out;
}

}  // namespace gearnvh::render
