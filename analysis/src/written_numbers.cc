#include "gearnvh/analysis/written_numbers.h"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <string>

namespace gearnvh {

double AsWritten(double v) { return std::isfinite(v) ? std::stod(fmt::format("{:.12g}", v)) : v; }

double Rpm(double rad_s) { return AsWritten(rad_s * 60.0 / (2.0 * std::numbers::pi)); }

}  // namespace gearnvh
