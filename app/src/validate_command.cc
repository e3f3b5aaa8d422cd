#include "validate_command.h"

#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "gearnvh/model/input_error.h"
#include "validation_ladder.h"

namespace gearnvh::app {

int RunValidate(const ValidateOptions& options) {
  try {
    const GearboxSpec spec = config::LoadGearboxFile(options.file);
    const std::vector<ValidationRow> rows = RunValidationLadder(spec);
    bool all = true;
    nlohmann::json checks = nlohmann::json::array();
    for (const ValidationRow& r : rows) {
      all = all && r.pass;
      checks.push_back({{"name", r.name},
                        {"value", r.value},
                        {"threshold", r.threshold},
                        {"pass", r.pass},
                        {"skipped", r.skipped},
                        {"detail", r.detail}});
    }
    if (options.json) {
      std::cout << nlohmann::json{{"name", spec.name},
                                  {"file", options.file},
                                  {"checks", checks},
                                  {"pass", all}}
                       .dump(2)
                << "\n";
    } else {
      fmt::print("{}  ({}): validation ladder\n", spec.name, options.file);
      fmt::print("  {:<50}{:>12}{:>12}  {}\n", "check", "value", "threshold", "result");
      for (const ValidationRow& r : rows) {
        fmt::print("  {:<50}{:>12.3e}{:>12.3e}  {}\n", r.name, r.value, r.threshold,
                   r.skipped ? "skipped" : (r.pass ? "pass" : "FAIL"));
        if (!r.detail.empty()) fmt::print("      {}\n", r.detail);
      }
      fmt::print("  {}\n", all ? "all checks passed" : "SOME CHECKS FAILED");
    }
    return all ? 0 : 1;
  } catch (const InputError& e) {
    std::cerr << "error: " << InputErrorMessage(e, options.file) << "\n";
    return 1;
  }
}

}  // namespace gearnvh::app
