// The library names its own arguments and option fields ("tier", "SolverOptions.cycles"), never a
// YAML path or a flag (docs/design.md §1). The user chose them at a YAML path (the CLI) or a
// keyword (Python): UserNamed renames the library's input errors to that name, keeping the value
// and the rule, so the message reads as the user wrote the input.
#pragma once

#include <functional>
#include <string>
#include <utility>

#include "gearnvh/model/input_error.h"
#include "gearnvh/nvh/periodic_orbit.h"
#include "gearnvh/reduction/reduced_model.h"

namespace gearnvh::app {

// Where the user set each input the library checks; the defaults are the CLI's. --cycles and
// --transient are range-checked while the command line is parsed, so they never reach the library;
// a pair's --tier the model cannot have is reported at analysis.tier, located at its line with the
// value written there (as before this mapping; the message's "got" is then the file's tier).
struct InputNames {
  std::string tier = "analysis.tier";                   // TierNotAvailable
  std::string cycles = "analysis.cycles";               // SolverOptions.cycles
  std::string transient = "analysis.transient_cycles";  // SolverOptions.transient_cycles
  std::string excitation = "operating.excitation";      // NoCommonPeriod
  std::string structure = "shafts";                     // StructureNotReducible
};

inline InputError UserNamed(const InputError& e, const InputNames& names = {}) {
  const std::string* path = nullptr;
  if (dynamic_cast<const TierNotAvailable*>(&e)) {
    path = &names.tier;
  } else if (dynamic_cast<const StructureNotReducible*>(&e)) {
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

// The wording of a failed atlas cell's or orbit point's input error (AtlasOptions::
// input_error_message): the message of UserNamed.
inline std::function<std::string(const InputError&)> UserWording(InputNames names = {}) {
  return [names = std::move(names)](const InputError& e) {
    return std::string(UserNamed(e, names).what());
  };
}

}  // namespace gearnvh::app
