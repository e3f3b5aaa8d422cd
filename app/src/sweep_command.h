// `gearnvh sweep FILE [--tier T] [--cycles N] [--transient N] [--jobs N] [--method M] [--out DIR]
// [--json]`: the speed sweep of analysis.speed_sweep — Campbell data (tracked modes, order lines,
// critical speeds) and a waterfall of steady-state TE spectra — as text, JSON and CSV files.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/order_tracks.h"
#include "gearnvh/analysis/speed_sweep.h"

namespace gearnvh::app {

struct SweepOptions {
  std::string file;
  std::optional<std::string> tier;
  std::optional<long> cycles;     // recorded cycles per speed (default 512)
  std::optional<long> transient;  // default 200
  int jobs = 0;                   // threads; 0 = all cores
  LadderMethod method = LadderMethod::kFused;
  std::optional<std::string> out;
  std::optional<std::string> uff;  // UFF dataset-58 file (order tracks)
  bool json = false;
  bool allow_slow = false;  // gear trains: run even when the cost estimate exceeds an hour
};

int RunSweep(const SweepOptions& options);

// The sweep's documents (also used by reports): JSON, and CSV of the Campbell data and critical
// speeds. `mesh_order` = z1.
nlohmann::json SweepJson(const SpeedSweepResult& r, double mesh_order);
std::string CampbellCsv(const SpeedSweepResult& r);
std::string CriticalCsv(const SpeedSweepResult& r);
// waterfall.csv of a pair's or a train's sweep: a row per speed and order bin of each waterfall
// (speed_rpm, order, frequency_hz, amplitude_m); with `names` (a train's meshes, one waterfall
// each) a `mesh` column after the speed. A failed speed has no rows.
std::string WaterfallCsv(const std::vector<WaterfallView>& waterfalls,
                         const std::vector<std::string>& names = {});

}  // namespace gearnvh::app
