#include "gearnvh/nvh/spectrum.h"

#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

namespace gearnvh {
namespace {


std::vector<double> Sample(int n, double rate, const std::function<double(double)>& f) {
  std::vector<double> x(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) x[static_cast<size_t>(i)] = f(i / rate);
  return x;
}

TEST_CASE("a pure tone on a bin reads its amplitude exactly", "[nvh][spectrum]") {
  // Hann window, amplitude-corrected: exact on a bin up to rounding (FFT of 4096 points: 1e-12);
  // a TE-like signal (7 um mean, 2.5 um tone) keeps the offset's rounding at that level.
  const int n = 4096;
  const double rate = 4096.0, f = 300.0, a = 2.5e-6;  // 1 Hz bins, the tone on bin 300
  SpectrumAnalyzer fft(n);
  const AmplitudeSpectrum s = fft.Analyze(
      Sample(n, rate, [&](double t) { return 7e-6 + a * std::sin(2 * std::numbers::pi * f * t); }), rate);
  CHECK(s.bin_hz == 1.0);
  CHECK(s.amplitude[300] == Approx(a).epsilon(1e-12));
  CHECK(s.amplitude[299] ==
        Approx(0.5 * a).epsilon(1e-12));  // Hann leakage: -6 dB on the neighbours
  CHECK(s.amplitude[0] < 1e-12 * a);      // the mean is removed
  CHECK(s.amplitude[310] < 1e-12 * a);
}

TEST_CASE("a pure tone off a bin: scalloping within the Hann bound, interpolation recovers it",
          "[nvh][spectrum]") {
  // Half a bin off, the Hann window loses at most 1.42 dB (factor 0.8488); the three-point
  // interpolation is exact for one tone up to the negative-frequency image's leakage (~1/N^2 here).
  const int n = 4096;
  const double rate = 4096.0, a = 1.0;
  SpectrumAnalyzer fft(n);
  for (double f : {300.5, 300.25, 777.8}) {
    const AmplitudeSpectrum s = fft.Analyze(
        Sample(n, rate, [&](double t) { return a * std::cos(2 * std::numbers::pi * f * t + 0.3); }), rate);
    const double raw = *std::max_element(s.amplitude.begin() + 1, s.amplitude.end());
    CHECK(raw >= 0.8488 * a);
    CHECK(raw <= a * (1 + 1e-12));
    const SpectralLine line = FindLine(s, f);
    CHECK(line.frequency_hz == Approx(f).margin(1e-4));
    CHECK(line.amplitude == Approx(a).epsilon(1e-5));
  }
}

TEST_CASE("an AM signal's sidebands are found at the right frequencies and amplitudes",
          "[nvh][spectrum][sidebands]") {
  // (1 + m cos(2 pi f1 t)) sin(2 pi fm t) = sin(2 pi fm t) + (m/2) [sin(2 pi (fm - f1) t) + sin(2
  // pi (fm + f1) t)]: carrier a, sidebands at fm +- f1 with a m / 2, nothing at fm +- f2. A record
  // of whole shaft revolutions puts every line on a bin, so the table is exact to rounding.
  const int z1 = 20, z2 = 30;
  const double f1 = 8.0, fm = z1 * f1, f2 = fm / z2;  // 160 Hz mesh, shafts at 8 and 5.33 Hz
  const double record = 3.0;                          // s: 24 pinion and 16 wheel revolutions
  const int n = 6144;
  const double rate = n / record, m = 0.4, a = 3e-6;
  SpectrumAnalyzer fft(n);
  const AmplitudeSpectrum s = fft.Analyze(Sample(n, rate,
                                                 [&](double t) {
                                                   return a * (1 + m * std::cos(2 * std::numbers::pi * f1 * t)) *
                                                          std::sin(2 * std::numbers::pi * fm * t);
                                                 }),
                                          rate);
  SidebandOptions options;
  options.harmonics = 2;
  options.orders = 1;
  const std::vector<SidebandRow> rows = SidebandTable(s, fm, f1, f2, options);
  auto has = [&](const std::string& label) {
    for (const auto& r : rows)
      if (r.label == label) return true;
    return false;
  };
  auto find = [&](const std::string& label) {
    for (const auto& r : rows)
      if (r.label == label) return r;
    FAIL("no row " << label);
    return SidebandRow{};
  };
  // The three real lines are listed, exact to rounding; their background is rounding noise.
  REQUIRE(rows.size() == 3);
  CHECK(find("1 fm").amplitude == Approx(a).epsilon(1e-9));
  CHECK(find("1 fm - 1 f1").amplitude == Approx(a * m / 2).epsilon(1e-9));
  CHECK(find("1 fm + 1 f1").amplitude == Approx(a * m / 2).epsilon(1e-9));
  CHECK(find("1 fm - 1 f1").frequency_hz == Approx(fm - f1));
  CHECK(find("1 fm").db_re_1um == Approx(20 * std::log10(a / 1e-6)).epsilon(1e-12));
  CHECK(find("1 fm").background < 1e-12 * a);
  // Lines that are not in the signal (rounding noise, ~-300 dB) are not listed.
  CHECK_FALSE(has("1 fm + 1 f2"));
  CHECK_FALSE(has("2 fm"));
  CHECK_FALSE(has("1 f1"));
  // Without shaft-order sources only mesh harmonics are considered.
  options.shaft_order_sources = false;
  const std::vector<SidebandRow> harmonics_only = SidebandTable(s, fm, f1, f2, options);
  REQUIRE(harmonics_only.size() == 1);
  CHECK(harmonics_only[0].label == "1 fm");
}

TEST_CASE("a sideband table with one named source: the input shaft's orders of a train mesh",
          "[nvh][spectrum][sidebands]") {
  // A train mesh whose frequency is not a whole order of the input (fm = 7.5 fin) modulated by
  // the engine's second order: a (1 + m cos(2 pi 2 fin t)) sin(2 pi fm t) + c sin(2 pi 2 fin t)
  // has the lines 2 fin (c), 1 fm (a) and 1 fm +- 2 fin (a m / 2) and nothing else. 3 s at
  // fin = 4 Hz holds 12 input revolutions and 90 mesh cycles: every line on a bin, exact to
  // rounding (1e-9 as the test above).
  const double fin = 4.0, fm = 7.5 * fin, record = 3.0;
  const int n = 3072;
  const double rate = n / record, m = 0.5, a = 2e-6, c = 5e-6;
  SpectrumAnalyzer fft(n);
  const AmplitudeSpectrum s = fft.Analyze(
      Sample(n, rate,
             [&](double t) {
               return a * (1 + m * std::cos(2 * std::numbers::pi * 2 * fin * t)) * std::sin(2 * std::numbers::pi * fm * t) +
                      c * std::sin(2 * std::numbers::pi * 2 * fin * t);
             }),
      rate);
  const std::vector<SidebandRow> rows = SidebandTable(s, fm, {{"fin", fin}});
  auto amplitude = [&](const std::string& label) {
    for (const auto& r : rows)
      if (r.label == label) return r.amplitude;
    FAIL("no row " << label);
    return 0.0;
  };
  REQUIRE(rows.size() == 4);
  CHECK(amplitude("2 fin") == Approx(c).epsilon(1e-9));
  CHECK(amplitude("1 fm") == Approx(a).epsilon(1e-9));
  CHECK(amplitude("1 fm - 2 fin") == Approx(a * m / 2).epsilon(1e-9));
  CHECK(amplitude("1 fm + 2 fin") == Approx(a * m / 2).epsilon(1e-9));
  // The pair's two-shaft table is this table with the sources f1 and f2.
  const std::vector<SidebandRow> pair = SidebandTable(s, fm, fin, 0.75 * fin);
  const std::vector<SidebandRow> named = SidebandTable(s, fm, {{"f1", fin}, {"f2", 0.75 * fin}});
  REQUIRE(pair.size() == named.size());
  for (size_t k = 0; k < pair.size(); ++k) {
    CHECK(pair[k].label == named[k].label);
    CHECK(pair[k].amplitude == named[k].amplitude);
  }
}

TEST_CASE("a mesh harmonic on a shaft order's bin is named first", "[nvh][spectrum][sidebands]") {
  // fm = 3 fin: 3 fin, 1 fm and 2 fm - 3 fin share one bin, 1 fm + 3 fin and 2 fm another; the
  // rows read "1 fm = ..." and "2 fm = ...", so they count as the mesh harmonics they are. 1 fin
  // is a shaft order (1 fm - 2 fin on its bin).
  const double fin = 4.0, fm = 3.0 * fin, record = 3.0;
  const int n = 3072;
  const double rate = n / record;
  SpectrumAnalyzer fft(n);
  const AmplitudeSpectrum s = fft.Analyze(Sample(n, rate,
                                                 [&](double t) {
                                                   return 2e-6 * std::sin(2 * std::numbers::pi * fm * t) +
                                                          1e-6 * std::sin(2 * std::numbers::pi * 2 * fm * t) +
                                                          3e-6 * std::sin(2 * std::numbers::pi * fin * t);
                                                 }),
                                          rate);
  std::vector<std::string> harmonics, others;
  for (const SidebandRow& r : SidebandTable(s, fm, {{"fin", fin}})) {
    (IsMeshHarmonic(r) ? harmonics : others).push_back(r.label);
  }
  REQUIRE(harmonics.size() == 2);
  CHECK(harmonics[0] == "1 fm = 3 fin = 2 fm - 3 fin");
  CHECK(harmonics[1] == "2 fm = 1 fm + 3 fin = 3 fm - 3 fin");
  CHECK(others == std::vector<std::string>{"1 fin = 1 fm - 2 fin"});
  CHECK(IsMeshHarmonic({"3 fm", 1.0}));
  CHECK(IsMeshHarmonic({"12 fm = 1 f1", 1.0}));
  CHECK_FALSE(IsMeshHarmonic({"1 fm + 1 f1", 1.0}));
  CHECK_FALSE(IsMeshHarmonic({"23 fin = 1 fm", 1.0}));
  CHECK_FALSE(IsMeshHarmonic({"fm", 1.0}));
}

TEST_CASE("a line buried in broadband noise is not listed as a sideband",
          "[nvh][spectrum][sidebands]") {
  // A carrier plus deterministic broadband "noise" (many incommensurate tones of 1e-2 a): a
  // sideband of 3e-3 a sits below the background and is not listed; one of 0.1 a is.
  const int z1 = 20, z2 = 30;
  const double f1 = 8.0, fm = z1 * f1, f2 = fm / z2;
  const double record = 3.0;
  const int n = 6144;
  const double rate = n / record, a = 1.0;
  auto signal = [&](double small, double t) {
    double v = a * std::sin(2 * std::numbers::pi * fm * t) + small * a * std::sin(2 * std::numbers::pi * (fm + f1) * t);
    for (int i = 1; i < 400; ++i) {
      v += 1e-2 * a * std::sin(2 * std::numbers::pi * (0.5 + 0.731 * i) * t + i);  // off-bin: leaks broadly
    }
    return v;
  };
  SpectrumAnalyzer fft(n);
  for (auto [small, listed] : {std::pair{3e-3, false}, {0.1, true}}) {
    const AmplitudeSpectrum s =
        fft.Analyze(Sample(n, rate, [&, small = small](double t) { return signal(small, t); }), rate);
    bool found = false;
    for (const SidebandRow& r : SidebandTable(s, fm, f1, f2)) found |= r.label == "1 fm + 1 f1";
    CHECK(found == listed);
  }
}

TEST_CASE("a signal at rest lists no line, whatever its rounding holds",
          "[nvh][spectrum][sidebands]") {
  // A TE at rest, 50 um, carrying a mesh-frequency ripple of 1e-21 m (the -334 dB its rounding
  // would hold): the floor is relative to the strongest bin with the mean included, so nothing is
  // listed; the same ripple at 1e-9 m (-94 dB) is a line.
  const double fm = 30.0, record = 3.0;
  const int n = 3072;
  const double rate = n / record, mean = 50e-6;
  SpectrumAnalyzer fft(n);
  for (auto [ripple, listed] : {std::pair{1e-21, false}, {1e-9, true}}) {
    const AmplitudeSpectrum s = fft.Analyze(
        Sample(n, rate,
               [&, ripple = ripple](double t) {
                 return mean + ripple * std::sin(2 * std::numbers::pi * fm * t);
               }),
        rate);
    const std::vector<SidebandRow> rows = SidebandTable(s, fm, {{"fin", 4.0}});
    INFO("ripple " << ripple);
    CHECK(rows.empty() == !listed);
  }
  // A TE at rest at 0 (a train without load): every bin is rounding, so the spectrum's own
  // strongest bin says nothing; relative to the half backlash (50 um) the 1e-22 m ripple is
  // -354 dB and not listed, a 1e-9 m one is.
  for (auto [ripple, listed] : {std::pair{1e-22, false}, {1e-9, true}}) {
    const AmplitudeSpectrum s = fft.Analyze(
        Sample(n, rate,
               [&, ripple = ripple](double t) {
                 return ripple * std::sin(2 * std::numbers::pi * fm * t);
               }),
        rate);
    SidebandOptions options;
    options.scale = 50e-6;
    INFO("ripple " << ripple << " about 0");
    CHECK(SidebandTable(s, fm, {{"fin", 4.0}}, options).empty() == !listed);
  }
}

}  // namespace
}  // namespace gearnvh
