// `gearnvh validate FILE [--json]`: runs the validation ladder (docs/design.md §8) on one gearbox
// and prints each row: check, measured value, threshold, pass/fail. Exit code 1 if any row fails.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "gearnvh/analysis/validation_ladder.h"

namespace gearnvh::app {

struct ValidateOptions {
  std::string file;
  bool json = false;
  bool allow_slow = false;  // gear trains: run a ladder estimated above an hour
};

int RunValidate(const ValidateOptions& options);

// `validate --json`: {name, file, checks, pass} (docs/cli.md).
nlohmann::json ValidationDocument(const std::vector<ValidationRow>& rows, const std::string& name,
                                  const std::string& file);

}  // namespace gearnvh::app
