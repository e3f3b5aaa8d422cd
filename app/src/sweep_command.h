// `gearnvh sweep FILE [--tier T] [--cycles N] [--transient N] [--jobs N] [--method M] [--out DIR]
// [--json]`: the speed sweep of analysis.speed_sweep — Campbell data (tracked modes, order lines,
// critical speeds) and a waterfall of steady-state TE spectra — as text, JSON and CSV files.
#pragma once

#include <optional>
#include <string>

namespace gearnvh::app {

struct SweepOptions {
  std::string file;
  std::optional<std::string> tier;
  std::optional<long> cycles;     // recorded cycles per speed (default 512)
  std::optional<long> transient;  // default 200
  int jobs = 0;                   // threads; 0 = all cores
  std::string method = "fused";
  std::optional<std::string> out;
  bool json = false;
};

int RunSweep(const SweepOptions& options);

}  // namespace gearnvh::app
