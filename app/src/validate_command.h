// `gearnvh validate FILE [--json]`: runs the validation ladder (docs/design.md §8) on one gearbox and
// prints each row: check, measured value, threshold, pass/fail. Exit code 1 if any row fails.
#pragma once

#include <string>

namespace gearnvh::app {

struct ValidateOptions {
  std::string file;
  bool json = false;
};

int RunValidate(const ValidateOptions& options);

}  // namespace gearnvh::app
