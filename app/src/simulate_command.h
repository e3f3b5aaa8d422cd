// `gearnvh simulate FILE [--tier T] [--cycles N] [--out DIR] [--json]`: one operating point through
// the exact solver; prints the summary (text or JSON); --out writes trajectory.csv, events.csv and
// results.json atomically. A schema-2 file (gear train) runs the train solver instead
// (simulate_train.h).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "gearnvh/model/component_model.h"
#include "gearnvh/solver/exact_solver.h"

namespace gearnvh::app {

struct SimulateOptions {
  std::string file;
  std::optional<std::string>
      tier;                    // overrides analysis.tier: 1..5, "N40 full", "N20 simple", "N20 MTA"
  std::optional<long> cycles;  // overrides analysis.cycles
  std::optional<long> transient;   // overrides analysis.transient_cycles
  std::optional<std::string> out;  // output directory
  std::optional<std::string> uff;  // UFF dataset-58 file (TE, mesh force, TE spectrum)
  LadderMethod method = LadderMethod::kFused;
  bool json = false;
  // Gear trains: the K largest Lyapunov exponents (tangents with saltation, a second run).
  std::optional<int> lyapunov;
  bool allow_slow = false;  // gear trains: run even when the cost estimate exceeds an hour
};

int RunSimulate(const SimulateOptions& options);

// --tier: 1..5, "N40 full", "N20 simple", "N20 MTA"; InputError otherwise.
Tier ParseTier(const std::string& text, const std::string& field = "--tier");
// A tier `model` cannot have, refused before any work at the name the user chose it by
// (PairTierNames): --tier with the text given (a usage error), else analysis.tier.
void RequirePairTier(const ComponentModel& model, Tier tier,
                     const std::optional<std::string>& tier_option);
// --method: v1, v2, v3 or fused (LadderMethodName); InputError naming `field`, the value and the
// choices otherwise. The one place a method's name becomes a LadderMethod.
LadderMethod ParseMethod(const std::string& text, const std::string& field = "--method");

}  // namespace gearnvh::app
