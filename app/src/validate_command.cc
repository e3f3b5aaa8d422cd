#include "validate_command.h"

#include <fmt/format.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "command_errors.h"
#include "config/gearbox_loader.h"
#include "gearnvh/analysis/train_validation.h"
#include "gearnvh/analysis/validation_ladder.h"
#include "gearnvh/model/input_error.h"

namespace gearnvh::app {

nlohmann::json ValidationDocument(const std::vector<ValidationRow>& rows, const std::string& name,
                                  const std::string& file) {
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
  return {{"name", name}, {"file", file}, {"checks", checks}, {"pass", all}};
}

int RunValidate(const ValidateOptions& options) {
  return RunReportingErrors(options.file, [&](config::SourceLocations& where) -> int {
    const config::LoadedGearbox loaded = config::LoadAnyGearboxFile(options.file);
    where = loaded.locations;
    const std::string name = loaded.schema == 2 ? loaded.train.name : loaded.pair->name;
    std::vector<ValidationRow> rows;
    if (loaded.schema == 2) {
      TrainValidationOptions ladder;
      ladder.allow_slow = options.allow_slow;
      ladder.before_run_warning = [](const std::string& w) {
        std::cerr << "warning: " << w << "\n";
      };
      rows = RunTrainValidationLadder(loaded.train, ladder);
    } else {
      rows = RunValidationLadder(*loaded.pair);
    }
    const nlohmann::json doc = ValidationDocument(rows, name, options.file);
    const bool all = doc["pass"].get<bool>();
    if (options.json) {
      std::cout << doc.dump(2) << "\n";
    } else {
      fmt::print("{}  ({}): validation ladder\n", name, options.file);
      fmt::print("  {:<50}{:>12}{:>12}  {}\n", "check", "value", "threshold", "result");
      for (const ValidationRow& r : rows) {
        fmt::print("  {:<50}{:>12.3e}{:>12.3e}  {}\n", r.name, r.value, r.threshold,
                   r.skipped ? "skipped" : (r.pass ? "pass" : "FAIL"));
        if (!r.detail.empty()) fmt::print("      {}\n", r.detail);
      }
      fmt::print("  {}\n", all ? "all checks passed" : "SOME CHECKS FAILED");
    }
    return all ? kExitOk : kExitInput;
  });
}

}  // namespace gearnvh::app
