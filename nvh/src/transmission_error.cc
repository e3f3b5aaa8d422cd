#include "gearnvh/nvh/transmission_error.h"

#include <algorithm>
#include <cmath>

namespace gearnvh {

TransmissionErrorStats ComputeTransmissionErrorStats(const Trajectory& trajectory,
                                                     double static_mesh_force) {
  TransmissionErrorStats s;
  const auto& p = trajectory.samples;
  s.samples = static_cast<int>(p.size());
  if (p.size() < 2) return s;
  const double span = p.back().time - p.front().time;
  double integral = 0.0, force_integral = 0.0;
  double lo = p.front().te, hi = lo;
  s.mesh_force_max = p.front().mesh_force;
  for (size_t i = 1; i < p.size(); ++i) {
    const double dt = p[i].time - p[i - 1].time;
    integral += 0.5 * dt * (p[i].te + p[i - 1].te);
    force_integral += 0.5 * dt * (p[i].mesh_force + p[i - 1].mesh_force);
    lo = std::min(lo, p[i].te);
    hi = std::max(hi, p[i].te);
    s.mesh_force_max = std::max(s.mesh_force_max, p[i].mesh_force);
  }
  s.mean = integral / span;
  s.mesh_force_mean = force_integral / span;
  double square = 0.0;
  for (size_t i = 1; i < p.size(); ++i) {
    const double dt = p[i].time - p[i - 1].time;
    const double a = p[i].te - s.mean, b = p[i - 1].te - s.mean;
    square += 0.5 * dt * (a * a + b * b);
  }
  s.rms = std::sqrt(square / span);
  s.peak_to_peak = hi - lo;
  s.dynamic_factor = static_mesh_force > 0.0 ? s.mesh_force_max / static_mesh_force : 0.0;
  return s;
}

}  // namespace gearnvh
