// The library names its own arguments and option fields ("tier", "SolverOptions.cycles"), never a
// YAML path or a flag (docs/design.md §1). The user chose them at a YAML path (the CLI) or a
// keyword (Python): UserNamed renames the library's input errors to that name, keeping the value
// and the rule, so the message reads as the user wrote the input.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "config/gearbox_loader.h"
#include "gearnvh/model/gearbox_spec_limits.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/nvh/periodic_orbit.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh::app {

// Where the user set each input the library checks; the defaults are the CLI's. --cycles and
// --transient are range-checked while the command line is parsed, so they never reach the library;
// a --tier the model cannot have is named at the flag with the text given (PairTierNames).
struct InputNames {
  std::string tier = "analysis.tier";                              // TierNotAvailable
  std::string cycles = "analysis.cycles";                          // SolverOptions.cycles
  std::string transient = "analysis.transient_cycles";             // SolverOptions.transient_cycles
  std::string excitation = "operating.excitation";                 // NoCommonPeriod
  std::string structure = "shafts";                                // StructureNotReducible
  std::string tier_value = "";  // the tier as the user wrote it; "": the tier's name
};

// The names of a pair command whose tier is --tier when given, else analysis.tier.
inline InputNames PairTierNames(const std::optional<std::string>& tier_option) {
  InputNames names;
  if (tier_option) {
    names.tier = "--tier";
    names.tier_value = *tier_option;
  }
  return names;
}

inline InputError UserNamed(const InputError& e, const InputNames& names = {}) {
  if (dynamic_cast<const TierNotAvailable*>(&e)) {
    return InputError(names.tier, e.line(), names.tier_value.empty() ? e.value() : names.tier_value,
                      e.rule(), e.source());
  }
  const std::string* path = nullptr;
  if (dynamic_cast<const StructureNotReducible*>(&e)) {
    path = &names.structure;
  } else if (dynamic_cast<const NoCommonPeriod*>(&e)) {
    path = &names.excitation;
  } else if (e.path() == "SolverOptions.cycles") {
    path = &names.cycles;
  } else if (e.path() == "SolverOptions.transient_cycles") {
    path = &names.transient;
  }
  if (path == nullptr) return e;
  return InputError(*path, e.line(), e.value(), e.rule(), e.source());
}

// How an axis value is shown to the user ("-10 µm"); empty: as the library holds it (SI).
using ParameterShown = std::function<std::string(const ParameterValue&)>;

// The wording of a failed atlas cell's or orbit point's input error (AtlasOptions::
// input_error_message): the message of UserNamed, an error at an axis's parameter with the
// cell's value as `shown` words it (config::AtParameterValue), as a train's cells are worded.
inline std::function<std::string(const InputError&, const std::vector<ParameterValue>&)>
UserWording(InputNames names = {}, ParameterShown shown = {}) {
  return [names = std::move(names), shown = std::move(shown)](
             const InputError& e, const std::vector<ParameterValue>& set) {
    const InputError named = UserNamed(e, names);
    return std::string((shown ? config::AtParameterValue(named, set, shown) : named).what());
  };
}

}  // namespace gearnvh::app
