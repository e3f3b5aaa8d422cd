// Amplitude spectra of uniformly sampled signals with FFTW (DESIGN.md §6), and the mesh-harmonic /
// sideband table an NVH engineer reads off a TE spectrum.
//
// Amplitude-correct one-sided spectrum with a Hann window w_n = 0.5 (1 - cos(2 pi n / N)):
//   A_k = 2 |sum_n w_n x_n e^{-2 pi i k n / N}| / sum_n w_n   (k > 0; A_0 without the factor 2),
// so a sine of amplitude a at an exact bin reads a. Off a bin the Hann window's scalloping loss is
// at most 1.42 dB (-15.1 %, half a bin off); the peak search below corrects it by the window's
// 3-point interpolation (amplitude and frequency of the dominant bin and its neighbours). The
// caller supplies whole mesh cycles so the periodic content sits on bins.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace gearnvh {

struct AmplitudeSpectrum {
  double bin_hz = 0.0;            // frequency resolution fs / N
  std::vector<double> amplitude;  // per bin k = 0 .. N/2, in the signal's unit
};

// Reusable FFTW plan for one length (plans are expensive; a sweep reuses one per length).
class SpectrumAnalyzer {
 public:
  explicit SpectrumAnalyzer(int length);
  ~SpectrumAnalyzer();
  SpectrumAnalyzer(const SpectrumAnalyzer&) = delete;
  SpectrumAnalyzer& operator=(const SpectrumAnalyzer&) = delete;

  int length() const { return n_; }
  // `samples` has exactly length() values taken at `sample_rate_hz`; the mean is removed first.
  AmplitudeSpectrum Analyze(const std::vector<double>& samples, double sample_rate_hz);

 private:
  struct Plan;
  int n_;
  std::unique_ptr<Plan> plan_;
  std::vector<double> window_;
  double window_sum_ = 0.0;
};

// A peak near `frequency_hz` (searched within +-search_bins), refined by Hann interpolation.
struct SpectralLine {
  double frequency_hz = 0.0;
  double amplitude = 0.0;
};
SpectralLine FindLine(const AmplitudeSpectrum& s, double frequency_hz, int search_bins = 2);

// Mesh harmonics k f_m (k = 1..harmonics) and sidebands k f_m +- j f_shaft (j = 1..orders) for the
// pinion and wheel shafts: one row per line with its order label, frequency, amplitude and dB
// (re 1 unit, 20 log10). The record must span whole revolutions of both shafts (a multiple of
// lcm(z1, z2) mesh cycles) so that every line sits on a bin; the bin is read as is.
struct SidebandRow {
  std::string label;  // e.g. "2 fm", "1 fm + 1 f1", "3 fm - 2 f2"
  double frequency_hz = 0.0;
  double amplitude = 0.0;
  double db = 0.0;
};
std::vector<SidebandRow> SidebandTable(const AmplitudeSpectrum& s, double mesh_hz, double pinion_hz,
                                       double wheel_hz, int harmonics, int orders);

}  // namespace gearnvh
