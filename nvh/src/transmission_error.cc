#include "gearnvh/nvh/transmission_error.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

std::vector<double> ResampleTe(const Trajectory& trajectory, double start, double rate_hz,
                               long count) {
  const auto& p = trajectory.samples;
  std::vector<double> out;
  if (count <= 0) return out;
  const double end = start + static_cast<double>(count - 1) / rate_hz;
  if (p.size() < 2 || start < p.front().time || end > p.back().time * (1.0 + 1e-12)) {
    throw std::out_of_range("ResampleTe: requested times outside the recorded trajectory");
  }
  out.reserve(static_cast<size_t>(count));
  size_t i = 0;
  for (long k = 0; k < count; ++k) {
    const double t = std::min(start + static_cast<double>(k) / rate_hz, p.back().time);
    while (i + 2 < p.size() && p[i + 1].time < t) ++i;
    const TrajectorySample& a = p[i];
    const TrajectorySample& b = p[i + 1];
    const double h = b.time - a.time;
    if (!(h > 0.0)) {
      out.push_back(a.te);
      continue;
    }
    const double u = (t - a.time) / h, u2 = u * u, u3 = u2 * u;
    out.push_back((2 * u3 - 3 * u2 + 1) * a.te + (u3 - 2 * u2 + u) * h * a.te_rate +
                  (-2 * u3 + 3 * u2) * b.te + (u3 - u2) * h * b.te_rate);
  }
  return out;
}

AmplitudeSpectrum TeSpectrum(const Trajectory& trajectory, double mesh_period,
                             int samples_per_cycle, long cycles, SpectrumAnalyzer& analyzer) {
  const long count = cycles * samples_per_cycle;
  if (analyzer.length() != count) {
    throw std::invalid_argument("TeSpectrum: analyzer length differs from cycles * samples");
  }
  const double rate = samples_per_cycle / mesh_period;
  // The window [end - cycles T, end): count samples, the last one a step before the end.
  const double start = trajectory.samples.back().time - static_cast<double>(cycles) * mesh_period;
  return analyzer.Analyze(ResampleTe(trajectory, start, rate, count), rate);
}

}  // namespace gearnvh
