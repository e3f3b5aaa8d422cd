// Small HTML helpers shared by the report's pages: escaping, table rows, numbers, the style
// sheet and the image check a headless browser reads.
#pragma once

#include <string>
#include <vector>

namespace gearnvh::app {

// `s` with &, <, > and " escaped.
std::string Html(const std::string& s);
// <tr><td>name</td><td>value</td></tr>, both escaped.
std::string Row(const std::string& name, const std::string& value);
// `digits` significant digits as Significant writes them ("12000"); "-" when not finite.
std::string Number(double v, int digits = 4);

// The speed sweep's points in a sentence: "6 speeds, 2 failed; 7000 rpm: why; 9000 rpm: why" (the
// failed ones with their messages, escaped). `Point` has speed_rpm, ok and message (a pair's
// SpeedPoint, a train's TrainSweepPoint).
template <typename Point>
std::string SweepSpeedsHtml(const std::vector<Point>& points, const std::string& speeds) {
  int failed = 0;
  std::string why;
  for (const Point& p : points) {
    if (p.ok) continue;
    ++failed;
    why += "; " + Number(p.speed_rpm) + " rpm: " + Html(p.message);
  }
  return std::to_string(points.size()) + " " + speeds + ", " + std::to_string(failed) + " failed" +
         why;
}

// The pages' style sheet (a <style> element).
extern const char* const kReportStyle;
// Marks images that did not load and counts them in data attributes of <body>
// (data-images-total, data-images-broken) a headless browser can read (a <script> element).
extern const char* const kImageCheckScript;

}  // namespace gearnvh::app
