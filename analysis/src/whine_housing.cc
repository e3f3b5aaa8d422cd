#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>

#include "gearnvh/model/input_error.h"
#include "whine_parts.h"

namespace gearnvh::whine {
namespace {

std::string BearingText(const std::string& shaft, int index) {
  return index >= 0 ? fmt::format("{}.bearings[{}]", shaft, index) : shaft + " support";
}

// The curve's transfer at `f` Hz, linear in its real and imaginary parts between its points;
// none outside its range.
std::optional<std::complex<double>> TransferAt(const HousingCurve& c, double f) {
  const std::vector<double>& x = c.frequency_hz;
  if (x.empty() || f < x.front() || f > x.back()) return std::nullopt;
  const size_t hi = static_cast<size_t>(std::lower_bound(x.begin(), x.end(), f) - x.begin());
  if (x[hi] == f) return c.transfer[hi];
  const double t = (f - x[hi - 1]) / (x[hi] - x[hi - 1]);
  return (1.0 - t) * c.transfer[hi - 1] + t * c.transfer[hi];
}

}  // namespace

std::vector<ResolvedCurve> ResolveHousing(const HousingTransfer& housing, const WhineResult& r) {
  if (r.bearings.empty()) {
    throw InputError("housing", 0, housing.source,
                     "needs bearing forces: tier 2 or higher (tier 1 has no lateral DOF)",
                     housing.source);
  }
  std::vector<ResolvedCurve> curves;
  for (const HousingCurve& c : housing.curves) {
    size_t b = 0;
    while (b < r.bearings.size() &&
           !(r.bearings[b].shaft == c.shaft && r.bearings[b].index == c.bearing))
      ++b;
    if (b == r.bearings.size()) {
      std::string names;
      for (const WhineBearing& w : r.bearings)
        names += (names.empty() ? "" : ", ") + BearingText(w.shaft, w.index);
      throw InputError("bearing", c.line, BearingText(c.shaft, c.bearing),
                       "must be a bearing of the gearbox: " + names, housing.source);
    }
    curves.push_back({&c, b});
  }
  return curves;
}

double HousingResponse(const std::vector<ResolvedCurve>& curves, double w,
                       const HarmonicResponse& out) {
  std::complex<double> sum = 0.0;
  for (const ResolvedCurve& c : curves) {
    const std::optional<std::complex<double>> t =
        TransferAt(*c.curve, w / (2.0 * std::numbers::pi));
    if (!t) return std::numeric_limits<double>::quiet_NaN();
    sum += *t * out.bearing_force[c.bearing][c.curve->direction];
  }
  return std::abs(sum);
}

}  // namespace gearnvh::whine
