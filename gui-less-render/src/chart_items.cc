#include "chart_items.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkContext2D.h>
#include <vtkContextItem.h>
#include <vtkContextScene.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkRect.h>
#include <vtkStringArray.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <utility>

#include "gearnvh/render/layout.h"

namespace gearnvh::render {

namespace {

// Paints before the chart: fits the title and the axis titles to the image (their fonts shrink
// until they fit, down to 8 pt), draws the title centred in a band at the top, and gives the chart
// the rest of the image, so no title is clipped at small sizes.
class TitleBand : public vtkContextItem {
 public:
  static TitleBand* New();
  vtkTypeMacro(TitleBand, vtkContextItem) vtkChartXY* chart = nullptr;
  std::string title;
  DrawnLayout* layout = nullptr;

  bool Paint(vtkContext2D* painter) override {
    const double w = GetScene()->GetSceneWidth(), h = GetScene()->GetSceneHeight();
    layout->image = {0.0, 0.0, w, h};
    double band = 12.0;
    if (!title.empty()) {
      vtkNew<vtkTextProperty> prop;
      prop->SetColor(0.0, 0.0, 0.0);
      prop->SetJustificationToLeft();
      prop->SetVerticalJustificationToBottom();
      float b[4] = {0, 0, 0, 0};
      for (int size = 20; size >= 8; --size) {
        prop->SetFontSize(size);
        painter->ApplyTextProp(prop);
        painter->ComputeStringBounds(title.c_str(), b);
        if (b[2] <= w - 20.0) break;
      }
      const double x0 = 0.5 * (w - b[2]), y0 = h - 8.0 - b[3];
      painter->DrawString(static_cast<float>(x0), static_cast<float>(y0), title.c_str());
      layout->title = {x0, y0, x0 + b[2], y0 + b[3]};
      band = b[3] + 14.0;
    }
    FitAxisTitle(painter, chart->GetAxis(vtkAxis::BOTTOM), w - 60.0);
    FitAxisTitle(painter, chart->GetAxis(vtkAxis::LEFT), h - band - 70.0);
    chart->SetSize(vtkRectf(0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h - band)));
    return true;
  }

 private:
  // The axis title's font shrinks until its length (horizontal, whatever the axis' orientation)
  // is at most `room` px.
  static void FitAxisTitle(vtkContext2D* painter, vtkAxis* axis, double room) {
    vtkNew<vtkTextProperty> prop;
    prop->ShallowCopy(axis->GetTitleProperties());
    prop->SetOrientation(0.0);
    float b[4] = {0, 0, 0, 0};
    int size = 16;
    for (; size > 8; --size) {
      prop->SetFontSize(size);
      painter->ApplyTextProp(prop);
      painter->ComputeStringBounds(axis->GetTitle().c_str(), b);
      if (b[2] <= room) break;
    }
    axis->GetTitleProperties()->SetFontSize(size);
  }
};
vtkStandardNewMacro(TitleBand);

// Paints after the chart has laid out its axes and legend: text at data coordinates, placed
// (layout.h) so labels overlap neither each other, the title, the legend nor the point markers
// (one with no free place is left out), and records the layout (plots.h DrawnLayout).
class ChartLabels : public vtkContextItem {
 public:
  static ChartLabels* New();
  vtkTypeMacro(ChartLabels, vtkContextItem) vtkChartXY* chart = nullptr;
  DrawnLayout* layout = nullptr;
  const ChartText* text = nullptr;
  int font_size = 13;

  bool Paint(vtkContext2D* painter) override {
    vtkAxis* xa = chart->GetAxis(vtkAxis::BOTTOM);
    vtkAxis* ya = chart->GetAxis(vtkAxis::LEFT);
    const float* x1 = xa->GetPoint1();
    const float* x2 = xa->GetPoint2();
    const float* y1 = ya->GetPoint1();
    const float* y2 = ya->GetPoint2();
    auto map = [](vtkAxis* axis, double v, float p1, float p2) {
      double lo = axis->GetMinimum(), hi = axis->GetMaximum();
      if (axis->GetLogScaleActive()) v = std::log10(std::max(v, 1e-300));
      return p1 + static_cast<float>((v - lo) / (hi - lo)) * (p2 - p1);
    };
    const Box area{x1[0], y1[1], x2[0], y2[1]};
    layout->plot_area = area;
    layout->labels.clear();
    layout->legend.reset();
    std::vector<Box> obstacles;
    if (layout->title.x1 > layout->title.x0) obstacles.push_back(layout->title);
    if (chart->GetShowLegend() && chart->GetLegend() != nullptr) {
      const vtkRectf r = chart->GetLegend()->GetBoundingRect(painter);
      layout->legend = Box{r.GetX(), r.GetY(), r.GetX() + r.GetWidth(), r.GetY() + r.GetHeight()};
      obstacles.push_back(*layout->legend);
    }
    for (const ChartText::Marker& m : text->markers) {
      const double px = map(xa, m.x, x1[0], x2[0]), py = map(ya, m.y, y1[1], y2[1]);
      const double half = 0.5 * m.size + 1.0;
      obstacles.push_back({px - half, py - half, px + half, py + half});
    }
    AddLineObstacles(xa, ya, area, map, obstacles);
    layout->data_marks.assign(obstacles.begin() + (layout->legend ? 1 : 0) +
                                  (layout->title.x1 > layout->title.x0 ? 1 : 0),
                              obstacles.end());
    painter->GetTextProp()->SetFontSize(font_size);
    painter->GetTextProp()->SetColor(0.1, 0.1, 0.1);
    painter->GetTextProp()->SetOrientation(0.0);
    painter->GetTextProp()->SetJustificationToLeft();
    painter->GetTextProp()->SetVerticalJustificationToBottom();
    std::vector<LabelRequest> requests;
    std::vector<const TextLabel*> shown;
    int outside = 0;
    for (const TextLabel& l : text->labels) {
      const float px = map(xa, l.x, x1[0], x2[0]);
      const float py = map(ya, l.y, y1[1], y2[1]);
      if (!(px >= x1[0] && px <= x2[0] && py >= y1[1] && py <= y2[1])) {
        ++outside;
        continue;
      }
      float bounds[4] = {0, 0, 0, 0};
      painter->ComputeStringBounds(l.text.c_str(), bounds);
      requests.push_back({px, py, bounds[2], bounds[3]});
      shown.push_back(&l);
    }
    // Markers are obstacles, but a label belongs next to its own marker: keep the gap larger
    // than the marker radius.
    double gap = 4.0;
    for (const ChartText::Marker& m : text->markers) gap = std::max(gap, 0.5 * m.size + 2.0);
    const std::vector<std::optional<Box>> placed = PlaceLabels(requests, area, obstacles, gap);
    layout->labels_dropped = outside;
    for (size_t i = 0; i < placed.size(); ++i) {
      if (!placed[i]) {
        ++layout->labels_dropped;
        continue;
      }
      painter->DrawString(static_cast<float>(placed[i]->x0), static_cast<float>(placed[i]->y0),
                          shown[i]->text.c_str());
      layout->labels.push_back(*placed[i]);
    }
    layout->text.clear();
    if (layout->title.x1 > layout->title.x0) layout->text.push_back(layout->title);
    if (layout->legend) layout->text.push_back(*layout->legend);
    layout->text.insert(layout->text.end(), layout->labels.begin(), layout->labels.end());
    return true;
  }

 private:
  // The drawn lines as obstacles too: small boxes every 3 px along each segment inside the plot
  // area (one per 3 px cell), as wide as the line.
  template <typename Map>
  void AddLineObstacles(vtkAxis* xa, vtkAxis* ya, const Box& area, const Map& map,
                        std::vector<Box>& obstacles) const {
    std::set<std::pair<long, long>> cells;
    for (const ChartText::Polyline& l : text->lines) {
      const double half = 0.5 * l.width + 1.0;
      auto add = [&](double cx, double cy) {
        if (cx < area.x0 || cx > area.x1 || cy < area.y0 || cy > area.y1) return;
        if (!cells.insert({std::lround(cx / 3.0), std::lround(cy / 3.0)}).second) return;
        obstacles.push_back({cx - half, cy - half, cx + half, cy + half});
      };
      bool have_previous = false;
      double px0 = 0.0, py0 = 0.0;
      for (size_t k = 0; k < l.x->size(); ++k) {
        const double xv = (*l.x)[k], yv = (*l.y)[k];
        const bool drawable = std::isfinite(xv) && std::isfinite(yv) &&
                              (!xa->GetLogScaleActive() || xv > 0.0) &&
                              (!ya->GetLogScaleActive() || yv > 0.0);
        if (!drawable) {
          have_previous = false;
          continue;
        }
        const double px = map(xa, xv, area.x0, area.x1), py = map(ya, yv, area.y0, area.y1);
        if (!have_previous) {
          add(px, py);
        } else {
          const double length = std::hypot(px - px0, py - py0);
          const int steps = static_cast<int>(std::min(1e5, length / 3.0)) + 1;
          for (int j = 1; j <= steps; ++j) {
            const double t = static_cast<double>(j) / steps;
            add(px0 + t * (px - px0), py0 + t * (py - py0));
          }
        }
        px0 = px;
        py0 = py;
        have_previous = true;
      }
    }
  }
};
vtkStandardNewMacro(ChartLabels);

}  // namespace

void AddChartWithLayout(vtkContextView* view, vtkChartXY* chart, const std::string& title,
                        const ChartText* text, DrawnLayout* layout) {
  vtkNew<TitleBand> band;
  band->chart = chart;
  band->title = title;
  band->layout = layout;
  view->GetScene()->AddItem(band);
  chart->SetAutoSize(false);
  view->GetScene()->AddItem(chart);
  vtkNew<ChartLabels> labels;
  labels->chart = chart;
  labels->layout = layout;
  labels->text = text;
  view->GetScene()->AddItem(labels);
}

// Custom ticks for a log axis drawn in log10 units: positions log10(t), labels t.
void SetLogTicks(vtkAxis* axis, double lo, double hi) {
  vtkNew<vtkDoubleArray> positions;
  vtkNew<vtkStringArray> names;
  for (double t : LogTicks(lo, hi)) {
    positions->InsertNextValue(std::log10(t));
    char text[32];
    std::snprintf(text, sizeof(text), "%g", t);
    names->InsertNextValue(text);
  }
  axis->SetCustomTickPositions(positions, names);
}

}  // namespace gearnvh::render
