// Shared pieces of the bench/ harnesses: the machine's name, the bundled examples, and the timing
// rules every comparison uses (docs/BENCHMARKS.md).
#pragma once

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "config/gearbox_loader.h"

namespace gearnvh::bench {

using Clock = std::chrono::steady_clock;

inline double SecondsOnce(const std::function<void()>& f) {
  const auto t0 = Clock::now();
  f();
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Marginal cost of `extra` cycles: run(C) and run(C + extra) back to back, `pairs` times, and the
// median of the paired differences. Pairing cancels the set-up both runs pay and slow drifts of
// the machine; the median ignores a pair disturbed by another process (a best-of-3 subtraction
// can pair a lucky long run with an unlucky short one and overstate the speed many times).
inline double PairedMarginalSeconds(const std::function<void(bool longer)>& run, int pairs) {
  std::vector<double> differences;
  for (int p = 0; p < pairs; ++p) {
    const double short_run = SecondsOnce([&] { run(false); });
    const double long_run = SecondsOnce([&] { run(true); });
    differences.push_back(long_run - short_run);
  }
  return std::max(Median(differences), 0.0);
}

inline std::string Machine() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  }
  return "unknown CPU";
}

inline GearboxSpec Example(const std::string& name) {
  return config::LoadGearboxFile(std::string(GEARNVH_EXAMPLES_DIR) + "/" + name);
}

// The preprint's strong-rattle point (docs/BENCHMARKS.md, "The paper's operating point"):
// examples/flexible_shafts.yaml at 7548.387097 rpm (mesh frequency 3.9 kHz), 20 N m, one engine
// order 15.5 of 200000 rad/s^2.
inline GearboxSpec PaperPoint() {
  GearboxSpec s = Example("flexible_shafts.yaml");
  s.operating.speed = 7548.387097 * std::numbers::pi / 30.0;
  s.operating.torque = 20.0;
  s.operating.excitation = {{15.5, 200000.0, 0.0}};
  return s;
}

}  // namespace gearnvh::bench
