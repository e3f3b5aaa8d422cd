#include "finite_results.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "command_errors.h"

namespace gearnvh::app {

namespace {

void Walk(const nlohmann::json& j, const std::string& path, const std::string& what) {
  if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      Walk(it.value(), path.empty() ? it.key() : path + "." + it.key(), what);
    }
  } else if (j.is_array()) {
    for (size_t i = 0; i < j.size(); ++i) Walk(j[i], path + "[" + std::to_string(i) + "]", what);
  } else if (j.is_number_float()) {
    const double v = j.get<double>();
    if (!std::isfinite(v)) {
      throw NonFiniteResult(what + ": " + (path.empty() ? std::string("result") : path) + " is " +
                            (std::isnan(v) ? "NaN" : "infinite") +
                            " (a non-finite result is never reported; please report this input)");
    }
  }
}

}  // namespace

void RequireFinite(const nlohmann::json& doc, const std::string& what) { Walk(doc, "", what); }

std::string CsvNumber(double v, int precision) {
  std::ostringstream field;
  field.precision(precision);
  if (!std::isnan(v)) field << v;
  return field.str();
}

nlohmann::json ResultOrNull(bool ok, double v) { return ok ? nlohmann::json(v) : nullptr; }

double ResultFromJson(const nlohmann::json& j) { return j.is_null() ? kNoResult : j.get<double>(); }

nlohmann::json FiniteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nullptr; }

double RelativeDifference(double a, double b, double resolution) {
  return std::abs(a - b) / std::max(std::abs(b), resolution);
}

}  // namespace gearnvh::app
