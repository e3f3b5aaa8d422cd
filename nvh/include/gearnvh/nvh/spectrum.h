// Amplitude spectra of uniformly sampled signals with FFTW (docs/design.md §6), and the
// mesh-harmonic / sideband table an NVH engineer reads off a TE spectrum.
//
// Amplitude-correct one-sided spectrum with a Hann window w_n = 0.5 (1 - cos(2 pi n / N)):
//   A_k = 2 |sum_n w_n x_n e^{-2 pi i k n / N}| / sum_n w_n   (k > 0; A_0 without the factor 2),
// so a sine of amplitude a at an exact bin reads a. Off a bin the Hann window's scalloping loss is
// at most 1.42 dB (-15.1 %, half a bin off); the peak search below corrects it by the window's
// 3-point interpolation (amplitude and frequency of the dominant bin and its neighbours). The
// caller supplies whole mesh cycles so the periodic content sits on bins.
#pragma once

#include <cstddef>
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

// The memory one spectrum of `length` samples holds at its peak: the caller's samples, the
// analyzer's FFT input and window, FFTW's complex output, its plan's twiddle factors and the
// amplitudes (length / 2 + 1 each).
size_t SpectrumBytes(long length);

// A peak near `frequency_hz` (searched within +-search_bins), refined by Hann interpolation.
struct SpectralLine {
  double frequency_hz = 0.0;
  double amplitude = 0.0;
};
SpectralLine FindLine(const AmplitudeSpectrum& s, double frequency_hz, int search_bins = 2);

// The lines an NVH engineer reads off a TE spectrum: shaft orders j f1, j f2 (j = 1..orders), mesh
// harmonics k f_m (k = 1..harmonics) and their sidebands k f_m +- j f_shaft, each with its label,
// frequency, amplitude and dB (re 1 unit, 20 log10). The record must span whole revolutions of
// both shafts (a multiple of lcm(z1, z2) mesh cycles) so that every line sits on a bin; the bin is
// read as is (interpolating would mix in a neighbouring sideband one bin away).
// Only lines that stand out are listed: amplitude >= prominence_db above the local background
// (the median amplitude of the +-background_bins bins around the line, the 2 x guard_bins + 1
// nearest excluded: leakage of other lines, broadband rattle) and above rounding_floor_db
// relative to the strongest bin of the spectrum, the mean (bin 0) included, or to `scale` when
// that is larger (the exact solution's double-precision rounding lies near -300 dB of the
// quantities it is computed from: a TE at rest has only rounding in every bin, so its size says
// nothing; the mesh's half backlash does). Without a source of shaft-order content (no runout,
// pitch error or engine order: `shaft_order_sources` false) only the mesh harmonics are considered.
struct SidebandOptions {
  int harmonics = 3;            // >= 1
  int orders = 3;               // >= 0
  double prominence_db = 12.0;  // >= 0
  int background_bins = 32;     // > guard_bins
  int guard_bins = 3;           // >= 1
  double rounding_floor_db = -200.0;
  double scale = 0.0;  // the signal's natural size in its units (a TE: the half backlash), >= 0
  bool shaft_order_sources = true;
};
struct SidebandRow {
  std::string label;  // e.g. "1 f1", "2 fm", "1 fm + 1 f1", "3 fm - 2 f2"; "1 f1 = 3 f2" when
                      // two lines fall on one frequency, a mesh harmonic named first
                      // ("1 fm = 23 fin")
  double frequency_hz = 0.0;
  double amplitude = 0.0;   // m
  double db_re_1um = 0.0;   // 20 log10(amplitude / 1 µm)
  double background = 0.0;  // local median amplitude
};
// Whether a row is a mesh harmonic "k fm" (its label starts with it: a shaft order or sideband
// falling on the same bin is named after it, "1 fm = 23 fin").
bool IsMeshHarmonic(const SidebandRow& row);

std::vector<SidebandRow> SidebandTable(const AmplitudeSpectrum& s, double mesh_hz, double pinion_hz,
                                       double wheel_hz, const SidebandOptions& options = {});

// The same table with any list of shaft-order sources, each a label stem and its rotation
// frequency: lines j f and k fm +- j f for every source f (the pair's table is the sources
// {"f1", pinion_hz}, {"f2", wheel_hz}). Every source's orders must sit on bins of the record.
struct ShaftOrderSource {
  std::string name;  // e.g. "f1", "fin"
  double frequency_hz = 0.0;
};
std::vector<SidebandRow> SidebandTable(const AmplitudeSpectrum& s, double mesh_hz,
                                       const std::vector<ShaftOrderSource>& sources,
                                       const SidebandOptions& options = {});

}  // namespace gearnvh
