// Small HTML helpers shared by the report's pages: escaping, table rows, numbers, the style
// sheet and the image check a headless browser reads.
#pragma once

#include <string>

namespace gearnvh::app {

// `s` with &, <, > and " escaped.
std::string Html(const std::string& s);
// <tr><td>name</td><td>value</td></tr>, both escaped.
std::string Row(const std::string& name, const std::string& value);
// `digits` significant digits as Significant writes them ("12000"); "-" when not finite.
std::string Number(double v, int digits = 4);

// The pages' style sheet (a <style> element).
extern const char* const kReportStyle;
// Marks images that did not load and counts them in data attributes of <body>
// (data-images-total, data-images-broken) a headless browser can read (a <script> element).
extern const char* const kImageCheckScript;

}  // namespace gearnvh::app
