#include "gearnvh/nvh/transmission_error.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

namespace gearnvh {
namespace {

TEST_CASE("TE statistics of a sampled sine over whole periods", "[nvh][te]") {
  // delta = m0 + A sin(2 pi t / T): mean m0, RMS A / sqrt(2), p-p 2 A. Trapezoid on 400 uneven
  // samples per period integrates a periodic smooth function spectrally: 1e-12 relative.
  Trajectory t;
  const double A = 3e-6, m0 = 5e-5, T = 1e-3;
  const int n = 4000;
  for (int i = 0; i <= n; ++i) {
    // Uneven spacing (as segment boundaries are), still covering 10 whole periods.
    const double u = static_cast<double>(i) / n;
    const double time =
        10 * T *
        (u + 0.002 * std::sin(2 * std::numbers::pi * 10 * u) / (2 * std::numbers::pi * 10));
    TrajectorySample s;
    s.time = time;
    s.te = m0 + A * std::sin(2 * std::numbers::pi * time / T);
    s.mesh_force = 100.0 + 10.0 * std::sin(2 * std::numbers::pi * time / T);
    t.samples.push_back(s);
  }
  const TransmissionErrorStats st = ComputeTransmissionErrorStats(t, 100.0);
  CHECK(st.mean == Approx(m0).epsilon(1e-6));
  CHECK(st.rms == Approx(A / std::sqrt(2.0)).epsilon(1e-5));
  CHECK(st.peak_to_peak == Approx(2 * A).epsilon(1e-4));  // samples hit the extremes to ~(pi/400)^2
  CHECK(st.dynamic_factor == Approx(1.1).epsilon(1e-4));
}

TEST_CASE("TE statistics of fewer than two samples are empty", "[nvh][te]") {
  Trajectory t;
  t.samples.push_back({});
  const TransmissionErrorStats st = ComputeTransmissionErrorStats(t, 1.0);
  CHECK(st.samples == 1);
  CHECK(st.rms == 0.0);
}

}  // namespace
}  // namespace gearnvh
