// `gearnvh tiers FILE [--cycles N] [--transient N] [--json] [--out DIR]`: the modal truncation
// levels side by side (tiers 1-5 / N40 full, N20 simple, N20 MTA, N20 MTA + fusion): DOF, state
// dimension, lowest natural frequencies and their error against the full FE model, static mesh
// compliance error, TE RMS and rattle index at the operating point and their difference to the
// finest tier, and cost (matvec per cycle, us per cycle, real-time ratio, table bytes). A table on
// the terminal, JSON, and with --out tiers.json, tiers.csv and tiers.png (accuracy against cost).
#pragma once

#include <optional>
#include <string>

namespace gearnvh::app {

struct TiersCommandOptions {
  std::string file;
  std::optional<long> cycles;     // recorded cycles per tier (default min(analysis.cycles, 400))
  std::optional<long> transient;  // default min(analysis.transient_cycles, 200)
  std::optional<std::string> out;
  bool json = false;
};

int RunTiers(const TiersCommandOptions& options);

}  // namespace gearnvh::app
