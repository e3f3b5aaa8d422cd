#include "gearnvh/nvh/spectrum.h"

#include <fftw3.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <mutex>
#include <numbers>
#include <stdexcept>

namespace gearnvh {

namespace {
std::mutex& PlannerMutex() {
  static std::mutex mutex;
  return mutex;
}
}  // namespace

struct SpectrumAnalyzer::Plan {
  double* in = nullptr;
  fftw_complex* out = nullptr;
  fftw_plan plan = nullptr;
};

SpectrumAnalyzer::SpectrumAnalyzer(int length) : n_(length), plan_(std::make_unique<Plan>()) {
  if (length < 8) throw std::invalid_argument("SpectrumAnalyzer: length must be >= 8");
  plan_->in = fftw_alloc_real(static_cast<size_t>(n_));
  plan_->out = fftw_alloc_complex(static_cast<size_t>(n_ / 2 + 1));
  {
    // FFTW's planner is not thread-safe (only fftw_execute is): sweeps build analyzers in threads.
    const std::lock_guard<std::mutex> lock(PlannerMutex());
    plan_->plan = fftw_plan_dft_r2c_1d(n_, plan_->in, plan_->out, FFTW_ESTIMATE);
  }
  window_.resize(static_cast<size_t>(n_));
  for (int i = 0; i < n_; ++i) {
    window_[static_cast<size_t>(i)] = 0.5 * (1.0 - std::cos(2.0 * std::numbers::pi * i / n_));
    window_sum_ += window_[static_cast<size_t>(i)];
  }
}

SpectrumAnalyzer::~SpectrumAnalyzer() {
  {
    const std::lock_guard<std::mutex> lock(PlannerMutex());
    fftw_destroy_plan(plan_->plan);
  }
  fftw_free(plan_->in);
  fftw_free(plan_->out);
}

size_t SpectrumBytes(long length) {
  if (length <= 0) return 0;
  const auto n = static_cast<size_t>(length);
  // FFTW's plan keeps about n / 2 complex twiddle factors (measured 7.3 to 7.8 B per sample for
  // 65,536 to 4,194,304 samples, FFTW_ESTIMATE).
  return 3 * n * sizeof(double) + (n / 2 + 1) * (2 * sizeof(fftw_complex) + sizeof(double));
}

AmplitudeSpectrum SpectrumAnalyzer::Analyze(const std::vector<double>& samples, double rate) {
  if (static_cast<int>(samples.size()) != n_) {
    throw std::invalid_argument("SpectrumAnalyzer: expected " + std::to_string(n_) + " samples");
  }
  double mean = 0.0;
  for (double v : samples) mean += v;
  mean /= n_;
  for (int i = 0; i < n_; ++i) {
    plan_->in[i] = (samples[static_cast<size_t>(i)] - mean) * window_[static_cast<size_t>(i)];
  }
  fftw_execute(plan_->plan);
  AmplitudeSpectrum s;
  s.bin_hz = rate / n_;
  s.amplitude.resize(static_cast<size_t>(n_ / 2 + 1));
  for (int k = 0; k <= n_ / 2; ++k) {
    const double mag = std::hypot(plan_->out[k][0], plan_->out[k][1]);
    s.amplitude[static_cast<size_t>(k)] = (k == 0 ? 1.0 : 2.0) * mag / window_sum_;
  }
  return s;
}

SpectralLine FindLine(const AmplitudeSpectrum& s, double frequency_hz, int search_bins) {
  const int n = static_cast<int>(s.amplitude.size());
  const int center = static_cast<int>(std::lround(frequency_hz / s.bin_hz));
  int best = std::clamp(center, 1, n - 2);
  for (int k = std::max(1, center - search_bins); k <= std::min(n - 2, center + search_bins); ++k) {
    if (s.amplitude[static_cast<size_t>(k)] > s.amplitude[static_cast<size_t>(best)]) best = k;
  }
  // Hann interpolation: a tone at bin k + d (|d| <= 1/2) gives the neighbour ratio
  // r = A(k+1)/A(k) = (1 + d)/(2 - d), so d = (2r - 1)/(r + 1) (mirrored when the left neighbour is
  // larger); the amplitude follows from the Hann kernel |W(d)| = sinc(d) / (1 - d^2), W(0) = 1.
  const double a = s.amplitude[static_cast<size_t>(best - 1)];
  const double b = s.amplitude[static_cast<size_t>(best)];
  const double c = s.amplitude[static_cast<size_t>(best + 1)];
  double d = 0.0;
  if (b > 0.0) {
    const double r = std::max(a, c) / b;
    d = (2.0 * r - 1.0) / (r + 1.0);
    if (a > c) d = -d;
  }
  const double pd = std::numbers::pi * d;
  const double kernel = std::abs(d) < 1e-12 ? 1.0 : std::sin(pd) / (pd * (1.0 - d * d));
  SpectralLine line;
  line.frequency_hz = (best + d) * s.bin_hz;
  line.amplitude = b / kernel;
  return line;
}

bool IsMeshHarmonic(const SidebandRow& row) {
  const std::string& l = row.label;
  const size_t fm = l.find(" fm");
  if (fm == std::string::npos || fm == 0 || l.find_first_not_of("0123456789") != fm) return false;
  return fm + 3 == l.size() || l.compare(fm + 3, 3, " = ") == 0;
}

std::vector<SidebandRow> SidebandTable(const AmplitudeSpectrum& s, double mesh_hz, double pinion_hz,
                                       double wheel_hz, const SidebandOptions& options) {
  return SidebandTable(s, mesh_hz, {{"f1", pinion_hz}, {"f2", wheel_hz}}, options);
}

std::vector<SidebandRow> SidebandTable(const AmplitudeSpectrum& s, double mesh_hz,
                                       const std::vector<ShaftOrderSource>& sources,
                                       const SidebandOptions& options) {
  std::vector<SidebandRow> rows;
  const long bins = static_cast<long>(s.amplitude.size());
  if (bins < 4) return rows;
  const double nyquist = s.bin_hz * static_cast<double>(bins - 1);
  // The mean (bin 0) counts: the samples' rounding is relative to the whole signal, so a TE
  // that only sits at its mean (no line at all) has nothing but rounding in its other bins.
  const double strongest =
      std::max(options.scale, *std::max_element(s.amplitude.begin(), s.amplitude.end()));
  const double floor = strongest * std::pow(10.0, options.rounding_floor_db / 20.0);
  const double prominence = std::pow(10.0, options.prominence_db / 20.0);
  std::vector<double> around;
  auto add = [&](const std::string& label, double f, bool harmonic = false) {
    if (f <= s.bin_hz || f >= nyquist - s.bin_hz) return;
    const long k = std::lround(f / s.bin_hz);
    const double amp = s.amplitude[static_cast<size_t>(k)];
    around.clear();
    for (long i = std::max(1L, k - options.background_bins);
         i <= std::min(bins - 1, k + options.background_bins); ++i) {
      if (std::abs(i - k) > options.guard_bins)
        around.push_back(s.amplitude[static_cast<size_t>(i)]);
    }
    double background = 0.0;
    if (!around.empty()) {
      const auto middle = around.begin() + static_cast<long>(around.size() / 2);
      std::nth_element(around.begin(), middle, around.end());
      background = *middle;
    }
    if (amp < floor || amp < prominence * background || !(amp > 0.0)) return;
    // Lines that coincide (z2 a multiple of z1 puts 3 f2 on 1 f1) share one row.
    for (SidebandRow& r : rows) {
      if (std::lround(r.frequency_hz / s.bin_hz) == k) {
        r.label = harmonic ? label + " = " + r.label : r.label + " = " + label;
        return;
      }
    }
    rows.push_back({label, f, amp, 20.0 * std::log10(amp / 1e-6), background});
  };
  if (options.shaft_order_sources) {
    for (const auto& [name, f] : sources) {
      for (int j = 1; j <= options.orders; ++j) add(std::to_string(j) + " " + name, j * f);
    }
  }
  for (int k = 1; k <= options.harmonics; ++k) {
    const std::string fm = std::to_string(k) + " fm";
    add(fm, k * mesh_hz, true);
    if (!options.shaft_order_sources) continue;
    for (int j = 1; j <= options.orders; ++j) {
      for (const auto& [name, f] : sources) {
        add(fm + " - " + std::to_string(j) + " " + name, k * mesh_hz - j * f);
        add(fm + " + " + std::to_string(j) + " " + name, k * mesh_hz + j * f);
      }
    }
  }
  return rows;
}

}  // namespace gearnvh
