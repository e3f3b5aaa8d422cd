#include "gearnvh/nvh/transmission_error.h"

#include <stdexcept>

namespace gearnvh {

TransmissionErrorStats ComputeTransmissionErrorStats(const Trajectory& trajectory,
                                                     double static_mesh_force,
                                                     double half_backlash) {
  TransmissionErrorStats s;
  const TrajectoryStatistics& st = trajectory.statistics;
  s.duration = st.duration;
  if (!(st.duration > 0.0)) return s;
  s.mean = st.te.Mean(st.duration);
  s.mean_from_contact = s.mean - half_backlash;
  s.rms = st.te.Rms(st.duration);
  s.max = st.te.max;
  s.min = st.te.min;
  s.peak_to_peak = st.te.max - st.te.min;
  s.mesh_force_mean = st.mesh_force.Mean(st.duration);
  s.mesh_force_max = st.mesh_force.max;
  s.dynamic_factor = static_mesh_force > 0.0 ? s.mesh_force_max / static_mesh_force : 0.0;
  return s;
}

AmplitudeSpectrum TeSpectrum(const Trajectory& trajectory, double mesh_period,
                             int samples_per_cycle, long cycles, SpectrumAnalyzer& analyzer) {
  const long count = cycles * samples_per_cycle;
  if (analyzer.length() != count) {
    throw std::invalid_argument("TeSpectrum: analyzer length differs from cycles * samples");
  }
  const auto& p = trajectory.samples;
  if (static_cast<long>(p.size()) < count) {
    throw std::out_of_range("TeSpectrum: the trajectory holds fewer samples than the window");
  }
  std::vector<double> te(static_cast<size_t>(count));
  const size_t first = p.size() - static_cast<size_t>(count);
  for (size_t i = 0; i < te.size(); ++i) te[i] = p[first + i].te;
  return analyzer.Analyze(te, samples_per_cycle / mesh_period);
}

}  // namespace gearnvh
