// Loads gearbox YAML (schema gearnvh/1, or gearnvh/2 for trains) into a validated spec in SI units.
//
// This is the only place yaml-cpp is used. Every failure throws gearnvh::InputError naming the
// source, line, YAML path, the value as written and the broken rule, e.g.
//   rattle.yaml:14: mesh.backlash: must be > 0, got -100 um
// Unknown keys get a suggestion for the closest known key; duplicate keys are rejected.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "config/units.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::config {

// Parses YAML text. `source` names it in messages (a file name, or "<string>").
GearboxSpec LoadGearboxFromString(const std::string& text, const std::string& source = "<string>");

// Reads and parses a file (at most 16 MiB).
GearboxSpec LoadGearboxFile(const std::string& path);

// The text of a gearbox file (at most 16 MiB); InputError naming the file when it cannot be read.
std::string ReadGearboxText(const std::string& path);

// Either schema: a gearnvh/1 file gives its GearboxSpec and the train it means (TrainOf), a
// gearnvh/2 file its TrainSpec.
struct LoadedGearbox {
  int schema = 1;
  std::optional<GearboxSpec> pair;  // schema 1
  TrainSpec train;
};
LoadedGearbox LoadAnyGearboxFromString(const std::string& text,
                                       const std::string& source = "<string>");
LoadedGearbox LoadAnyGearboxFile(const std::string& path);

// An axis given on the command line, "PARAMETER=FROM:TO:POINTS" with units on FROM and TO
// (operating.speed=600rpm:3000rpm:24). Throws InputError naming `field` (the option).
AtlasAxis ParseAxisOption(const std::string& text, const std::string& field);

// The same for any set of parameters: `dimension_of` gives a parameter's dimension (nullopt: not
// a parameter, and `rejection` gives the rule to print for that name, e.g. with the accepted forms
// or a close match).
AtlasAxis ParseAxisOption(
    const std::string& text, const std::string& field,
    const std::function<std::optional<Dimension>(const std::string&)>& dimension_of,
    const std::function<std::string(const std::string&)>& rejection);

// An InputError raised after a file was loaded (by the model, the solver or a command, e.g. a tier
// the model cannot have) located in that file as it was last loaded from `source`: the line of its
// YAML path (or of the closest enclosing key written) and, when the path itself was written, the
// value as written. An error that already has a line, names a command-line option ("--tier") or
// comes from a source never loaded is returned unchanged (attributed to `source`).
InputError LocatedInSource(const InputError& e, const std::string& source);

// The closest of `candidates` to `word` by edit distance, or "" when none is close.
std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace gearnvh::config
