// Loads schema gearnvh/1 YAML into a validated GearboxSpec in SI units.
//
// This is the only place yaml-cpp is used. Every failure throws gearnvh::InputError naming the
// source, line, YAML path, the value as written and the broken rule, e.g.
//   rattle.yaml:14: mesh.backlash: must be > 0, got -100 um
// Unknown keys get a suggestion for the closest known key; duplicate keys are rejected.
#pragma once

#include <string>

#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh::config {

// Parses YAML text. `source` names it in messages (a file name, or "<string>").
GearboxSpec LoadGearboxFromString(const std::string& text, const std::string& source = "<string>");

// Reads and parses a file (at most 16 MiB).
GearboxSpec LoadGearboxFile(const std::string& path);

// The text of a gearbox file (at most 16 MiB); InputError naming the file when it cannot be read.
std::string ReadGearboxText(const std::string& path);

// An axis given on the command line, "PARAMETER=FROM:TO:POINTS" with units on FROM and TO
// (operating.speed=600rpm:3000rpm:24). Throws InputError naming `field` (the option).
AtlasAxis ParseAxisOption(const std::string& text, const std::string& field);

// The closest of `candidates` to `word` by edit distance, or "" when none is close.
std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace gearnvh::config
