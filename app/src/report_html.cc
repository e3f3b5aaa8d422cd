#include "report_html.h"

#include <fmt/format.h>

#include <cmath>

#include "display_units.h"

namespace gearnvh::app {

std::string Html(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Row(const std::string& name, const std::string& value) {
  return fmt::format("<tr><td>{}</td><td>{}</td></tr>\n", Html(name), Html(value));
}

std::string Number(double v, int digits) { return std::isfinite(v) ? Significant(v, digits) : "-"; }

const char* const kImageCheckScript = R"(<script>
window.addEventListener('load', function () {
  var images = Array.prototype.slice.call(document.images);
  var broken = images.filter(function (i) { return !(i.complete && i.naturalWidth > 0); });
  document.body.setAttribute('data-images-total', images.length);
  document.body.setAttribute('data-images-broken', broken.length);
  if (broken.length) {
    var p = document.createElement('p');
    p.className = 'warn';
    p.textContent = broken.length + ' image(s) did not load: ' +
        broken.map(function (i) { return i.getAttribute('src'); }).join(', ');
    document.body.insertBefore(p, document.body.firstChild);
  }
});
</script>)";

const char* const kReportStyle = R"(<style>
body { font-family: sans-serif; margin: 2em auto; max-width: 1250px; color: #222; }
table { border-collapse: collapse; margin: 0.5em 0 1.5em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.6em; text-align: right; }
th:first-child, td:first-child { text-align: left; }
th { background: #f0f0f0; }
figure { margin: 1em 0 2em; }
figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { color: #555; font-size: 0.9em; }
.warning { color: #8a4b00; background: #fff4e0; border-left: 4px solid #e0a030; padding: 0.3em 0.6em; }
.warn { color: #a00; font-weight: bold; }
.ok { color: #070; }
</style>)";

}  // namespace gearnvh::app
