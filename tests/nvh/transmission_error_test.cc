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

namespace gearnvh {
namespace {

TEST_CASE("Hermite resampling of TE is fourth order and keeps harmonic amplitudes",
          "[nvh][resample]") {
  // TE = a sin(3 w t) (the third mesh harmonic) sampled at 32 uneven points per cycle.
  const double a = 1e-6, w = 2 * std::numbers::pi * 1000.0, period = 1e-3;
  Trajectory t;
  const int per_cycle = 32;
  const long cycles = 64;
  for (long c = 0; c < cycles; ++c) {
    for (int j = 0; j < per_cycle; ++j) {
      // Uneven boundaries like a bisected segmentation: +-30 % jitter of the spacing.
      const double u = (j + 0.3 * std::sin(1.7 * j)) / per_cycle;
      const double time = (c + u) * period;
      t.samples.push_back({time, a * std::sin(3 * w * time), 3 * w * a * std::cos(3 * w * time)});
    }
  }
  t.samples.push_back({cycles * period, 0.0, 3 * w * a});
  // Pointwise: cubic Hermite error <= h^4 max|f''''| / 384, h <= 1.6 / 32 of a period.
  const double h = 1.6 * period / per_cycle;
  const double bound = std::pow(h, 4) * a * std::pow(3 * w, 4) / 384.0;
  const std::vector<double> uniform = ResampleTe(t, 0.5 * period, 32 / period, 256);
  double worst = 0.0;
  for (size_t k = 0; k < uniform.size(); ++k) {
    const double time = 0.5 * period + k * period / 32;
    worst = std::max(worst, std::abs(uniform[k] - a * std::sin(3 * w * time)));
  }
  CHECK(worst <= bound);
  CHECK(worst <= 2e-3 * a);  // and the bound itself is small: 0.14 % of the amplitude
  // The spectrum of the resampled record reads the third harmonic's amplitude within that error.
  SpectrumAnalyzer analyzer(static_cast<int>(32 * (cycles - 1)));
  const AmplitudeSpectrum s = TeSpectrum(t, period, 32, cycles - 1, analyzer);
  CHECK(FindLine(s, 3000.0).amplitude == Approx(a).epsilon(2e-3));
  CHECK_THROWS_AS(ResampleTe(t, -1.0, 1000.0, 10), std::out_of_range);
}

}  // namespace
}  // namespace gearnvh
