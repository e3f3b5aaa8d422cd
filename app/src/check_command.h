// `gearnvh check FILE... [--json]`: load, validate and print the derived basics of each gearbox.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gearnvh/model/component_model.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh::app {

struct CheckOptions {
  std::vector<std::string> files;
  bool json = false;
};

// The JSON document `check --json` prints for one gearbox (keys documented in docs/cli.md).
nlohmann::json CheckReport(const GearboxSpec& spec, const ComponentModel& model,
                           const ModalSummary& modes, const std::vector<ReducedModel>& tiers);

// A tier's static compliance error against the full FE model. None for tier 1: it keeps only the
// gear rotations, which the static compliance holds fixed, so it has no mesh compliance at all
// (its error would read as -100 %).
std::optional<double> ComplianceErrorVsFull(Tier tier, double error);
// That error as JSON (null for none) and as text ("n/a" for none, else like "1.23e-04").
nlohmann::json ComplianceErrorJson(std::optional<double> error);
std::string ComplianceErrorText(std::optional<double> error);

// Modes reported per model and tier.
constexpr int kReportedModes = 10;

// Every tier the model supports, reduced (tiers 4, 5 and N20 need shafts).
std::vector<ReducedModel> ReduceAvailableTiers(const ComponentModel& model);

// Runs the command; returns the process exit code (0 ok, 1 if any file was invalid).
int RunCheck(const CheckOptions& options);

}  // namespace gearnvh::app
