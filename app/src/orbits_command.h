// `gearnvh orbits FILE [--period M] [--sweep P=FROM:TO:N] [--tier T] [--transient N] [--method M]
// [--out DIR] [--json]`: period-M orbits by Newton shooting with Floquet multipliers, stability
// and the nearest stability boundary, at the file's operating point or along one parameter
// (nvh/orbit_scan.h). Says plainly when no stable orbit was found.
#pragma once

#include <complex>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/solver/solver_options.h"

namespace gearnvh::app {

struct OrbitsCommandOptions {
  std::string file;
  int period = 1;
  std::optional<std::string> sweep;  // PARAMETER=FROM:TO:POINTS
  std::optional<std::string> tier;
  std::optional<long> transient;
  LadderMethod method = LadderMethod::kV3;  // kFused locates events as kV3
  std::optional<std::string> out;
  bool json = false;
  bool allow_slow = false;  // gear trains: run even when the cost estimate exceeds an hour
};

int RunOrbits(const OrbitsCommandOptions& options);

// The longest period searched, in base periods (one limit for the CLI's --period and Python's
// period=, of a pair and of a train): Newton's cost grows with it, and longer orbits are chaos in
// practice.
inline constexpr int kMaxOrbitPeriod = 64;
// Throws InputError at `field` unless 1 <= period <= kMaxOrbitPeriod.
void RequireOrbitPeriod(int period, const std::string& field);

// Shared with the train's orbits (train_orbits_command.h):
// {"re", "im", "abs"} of one Floquet multiplier.
nlohmann::json MultiplierJson(std::complex<double> mu);
// "  No stable period-M orbit exists at ..." (the plain statement when none was found).
std::string NoStableOrbitText(int period, bool swept);
// "orbits: 42% (5/12 points)" on stderr when it is a terminal and the run is a sweep; else empty.
std::function<void(int, int)> OrbitsTerminalProgress(bool swept);
// The exit code of a run with `failed` of `total` points lost: 1 (saying so on stderr) or 0.
int ReportFailedOrbitPoints(int failed, size_t total);

}  // namespace gearnvh::app
