// The items painted with a chart that lay out its text (docs/reports.md, "Readable layout"):
// before the chart, a title band (the title fitted to the image and drawn centred above the chart,
// the axis titles shrunk to fit, the chart given the rest of the image); after it, the data labels
// placed by layout.h PlaceLabels clear of each other, the title, the legend, the markers and the
// lines, and the record of what was drawn (plots.h DrawnLayout).
#pragma once

#include <vtkAxis.h>
#include <vtkChartXY.h>
#include <vtkContextView.h>

#include <string>
#include <vector>

#include "gearnvh/render/plots.h"

namespace gearnvh::render {

// What the labels item reads when the view renders.
struct ChartText {
  std::vector<TextLabel> labels;  // most important first
  struct Marker {
    double x, y, size;  // data coordinates, diameter px
  };
  std::vector<Marker> markers;
  struct Polyline {
    const std::vector<double>*x, *y;  // data coordinates; non-finite points break the line
    double width;                     // px
  };
  std::vector<Polyline> lines;
};

// Adds the title band, `chart` and the labels item to `view`, in that order. `text` and `layout`
// must outlive the view's rendering; `layout` is filled when it renders.
void AddChartWithLayout(vtkContextView* view, vtkChartXY* chart, const std::string& title,
                        const ChartText* text, DrawnLayout* layout);

// Custom ticks for a log axis drawn in log10 units: positions log10(t), labels t (LogTicks).
void SetLogTicks(vtkAxis* axis, double lo, double hi);

}  // namespace gearnvh::render
