// The validation ladder of docs/design.md §8, run on one gearbox: each row a check with its
// measured value, its threshold and whether it passed. Rows that need a part the model lacks (MTA
// without shafts) are reported as skipped, not passed silently.
#pragma once

#include <atomic>
#include <string>
#include <vector>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

struct ValidationRow {
  std::string name;
  double value = 0.0;
  double threshold = 0.0;
  bool pass = false;
  bool skipped = false;
  std::string detail;  // units, what was compared, or why skipped
};

// A measured row (pass when value <= threshold) and a skipped one.
ValidationRow CheckRow(std::string name, double value, double threshold, std::string detail);
ValidationRow SkippedRow(std::string name, std::string why);

// `cancel` (SolverOptions::cancel) is passed to every run, table build and CVODE reference:
// RunCancelled once set. Not owned; null: never cancelled.
std::vector<ValidationRow> RunValidationLadder(const GearboxSpec& spec,
                                               const std::atomic<bool>* cancel = nullptr);

}  // namespace gearnvh
