#include "housing_table.h"

#include <cmath>
#include <complex>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "gearnvh/model/input_error.h"

namespace gearnvh::app {
namespace {

constexpr const char* kHeader = "frequency_hz,bearing,direction,real,imag";

std::string Trimmed(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return {};
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

// A cell as spreadsheets export it: trimmed, one pair of enclosing double quotes removed.
std::string Cell(const std::string& s) {
  const std::string t = Trimmed(s);
  return t.size() >= 2 && t.front() == '"' && t.back() == '"' ? t.substr(1, t.size() - 2) : t;
}

std::vector<std::string> Cells(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream row(line);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(Cell(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

double Number(const std::string& text, const char* column, int line, const std::string& path) {
  const std::string t = Trimmed(text);
  // strtod: an underflow (1e-320) is a number, as it should be, where stod throws.
  char* end = nullptr;
  const double v = t.empty() ? 0.0 : std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || !std::isfinite(v))
    throw InputError(column, line, t, "must be a finite number", path);
  return v;
}

// "input.bearings[0]" -> (input, 0); "output support" -> (output, -1).
std::pair<std::string, int> BearingOf(const std::string& text, int line, const std::string& path) {
  static const std::regex kIndexed(R"(^(.+)\.bearings\[(\d+)\]$)");
  static const std::regex kSupport(R"(^(.+) support$)");
  std::smatch m;
  if (std::regex_match(text, m, kIndexed)) {
    const std::string digits = m[2].str();
    if (digits.size() > 6)
      throw InputError("bearing", line, text, "must have a bearing index below 1000000", path);
    return {m[1].str(), std::stoi(digits)};
  }
  if (std::regex_match(text, m, kSupport)) return {m[1].str(), -1};
  throw InputError("bearing", line, text,
                   "must name a bearing as SHAFT.bearings[I] or \"SHAFT support\"", path);
}

}  // namespace

HousingTransfer ReadHousingTable(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("--housing", 0, path, "must be a readable CSV file", path);
  HousingTransfer table;
  table.source = path;
  std::map<std::tuple<std::string, int, int>, size_t> curve_of;
  bool header = false;
  int line_number = 0;
  for (std::string raw; std::getline(in, raw);) {
    ++line_number;
    // A UTF-8 byte-order mark (spreadsheet exports) is not part of the first line.
    if (line_number == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3);
    const std::string line = Trimmed(raw);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> cells = Cells(line);
    if (!header) {
      std::string joined;
      for (const std::string& c : cells) joined += (joined.empty() ? "" : ",") + c;
      if (joined != kHeader)
        throw InputError("header", line_number, line, std::string("must be ") + kHeader, path);
      header = true;
      continue;
    }
    if (cells.size() != 5)
      throw InputError("row", line_number, line, "must have 5 columns: " + std::string(kHeader),
                       path);
    const double f = Number(cells[0], "frequency_hz", line_number, path);
    const auto [shaft, bearing] = BearingOf(cells[1], line_number, path);
    const std::string& d = cells[2];
    if (d != "x" && d != "y" && d != "z")
      throw InputError("direction", line_number, d, "must be x, y or z", path);
    const int direction = d[0] - 'x';
    const std::complex<double> h(Number(cells[3], "real", line_number, path),
                                 Number(cells[4], "imag", line_number, path));
    const auto key = std::make_tuple(shaft, bearing, direction);
    auto it = curve_of.find(key);
    if (it == curve_of.end()) {
      it = curve_of.emplace(key, table.curves.size()).first;
      table.curves.push_back({shaft, bearing, direction, {}, {}, line_number});
    }
    HousingCurve& c = table.curves[it->second];
    if (!c.frequency_hz.empty() && !(f > c.frequency_hz.back())) {
      throw InputError("frequency_hz", line_number, cells[0],
                       "must ascend for each bearing and direction", path);
    }
    c.frequency_hz.push_back(f);
    c.transfer.push_back(h);
  }
  if (!header)
    throw InputError("header", line_number, path, std::string("must be ") + kHeader, path);
  if (table.curves.empty())
    throw InputError("row", line_number, path, "needs at least one row", path);
  return table;
}

}  // namespace gearnvh::app
