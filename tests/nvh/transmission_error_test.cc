#include "gearnvh/nvh/transmission_error.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

namespace gearnvh {
namespace {

TEST_CASE("TE statistics read the exact statistics of the recorded window", "[nvh][te]") {
  // Statistics of delta = m0 + A sin(w t) over whole periods, written as the recorder would:
  // int (delta - offset) = (m0 - offset) T, int (delta - offset)^2 = ((m0 - offset)^2 + A^2/2) T.
  const double A = 3e-6, m0 = 5e-5, T = 1e-2, offset = 4e-5, b = 2e-5;
  Trajectory t;
  TrajectoryStatistics& st = t.statistics;
  st.duration = T;
  st.te.offset = offset;
  st.te.has_offset = true;
  st.te.integral = (m0 - offset) * T;
  st.te.square_integral = ((m0 - offset) * (m0 - offset) + A * A / 2) * T;
  st.te.max = m0 + A;
  st.te.min = m0 - A;
  st.mesh_force.has_offset = true;
  st.mesh_force.integral = 100.0 * T;
  st.mesh_force.max = 110.0;
  const TransmissionErrorStats s = ComputeTransmissionErrorStats(t, 100.0, b);
  CHECK(s.mean == Approx(m0).epsilon(1e-15));
  CHECK(s.mean_from_contact == Approx(m0 - b).epsilon(1e-14));
  CHECK(s.rms == Approx(A / std::sqrt(2.0)).epsilon(1e-12));  // extended-precision integrals
  CHECK(s.peak_to_peak == Approx(2 * A).epsilon(1e-12));
  CHECK(s.mesh_force_mean == Approx(100.0).epsilon(1e-15));
  CHECK(s.dynamic_factor == Approx(1.1).epsilon(1e-15));
  // Nothing recorded: empty statistics, no division by zero.
  const TransmissionErrorStats empty = ComputeTransmissionErrorStats(Trajectory{}, 1.0, b);
  CHECK(empty.rms == 0.0);
  CHECK(empty.duration == 0.0);
}

TEST_CASE("the TE spectrum takes the last whole cycles of the uniform samples", "[nvh][te]") {
  // TE = a sin(3 w t) (the third mesh harmonic) sampled 32 times per cycle: on a bin, read exactly.
  const double a = 1e-6, period = 1e-3, w = 2 * std::numbers::pi / period;
  Trajectory t;
  const int per_cycle = 32;
  const long cycles = 64;
  for (long k = 0; k < cycles * per_cycle + 5; ++k) {
    const double time = k * period / per_cycle;
    TrajectorySample s;
    s.time = time;
    s.te = a * std::sin(3 * w * time);
    t.samples.push_back(s);
  }
  // A record that does not end on a cycle boundary is a caller error; here 5 extra samples are
  // dropped by asking for fewer cycles than recorded.
  t.samples.resize(static_cast<size_t>(cycles * per_cycle));
  SpectrumAnalyzer analyzer(static_cast<int>(per_cycle * 60));
  const AmplitudeSpectrum s = TeSpectrum(t, period, per_cycle, 60, analyzer);
  CHECK(FindLine(s, 3000.0).amplitude == Approx(a).epsilon(1e-12));
  SpectrumAnalyzer too_long(static_cast<int>(per_cycle * 65));
  CHECK_THROWS_AS(TeSpectrum(t, period, per_cycle, 65, too_long), std::out_of_range);
}

}  // namespace
}  // namespace gearnvh
