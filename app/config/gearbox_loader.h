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

#include "config/source_locations.h"
#include "config/units.h"
#include "gearnvh/model/gearbox_spec.h"
#include "gearnvh/model/input_error.h"
#include "gearnvh/model/spec_parameters.h"
#include "gearnvh/model/train_spec.h"

namespace gearnvh::config {

// Parses YAML text. `source` names it in messages (a file name, or "<string>").
GearboxSpec LoadGearboxFromString(const std::string& text, const std::string& source = "<string>");

// Reads and parses a file (at most 16 MiB).
GearboxSpec LoadGearboxFile(const std::string& path);

// The text of a gearbox file (at most 16 MiB); InputError naming the file when it cannot be read.
std::string ReadGearboxText(const std::string& path);

// Either schema: a gearnvh/1 file gives its GearboxSpec and the train it means (TrainOf), a
// gearnvh/2 file its TrainSpec. `locations` says where each YAML path was written, so an error
// raised after loading (by the model, the solver or a command) can name the line and the value as
// written (LocatedIn).
struct LoadedGearbox {
  int schema = 1;
  std::optional<GearboxSpec> pair;  // schema 1
  TrainSpec train;
  SourceLocations locations;
  // Set when analysis.speed_sweep was not written and the default sweep was clipped to the
  // pitch-line velocity limit (the commands that run the sweep print it as a note).
  std::string sweep_note;
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

// The unit the upper end of an axis option "PARAMETER=FROM:TO:POINTS" was written in, as a speed
// (rpm, rev/s, rad/s; for messages about an axis varying operating.speed).
DisplayUnit SpeedUnitOfAxisOption(const std::string& text);

// A parameter of a pair's atlas axis or orbit sweep that SetParameter can set on `spec` (the
// file has the excitation order it varies), else InputError naming `field` (the option or the
// YAML path the name came from).
void RequireVariableParameter(const GearboxSpec& spec, const std::string& parameter,
                              const std::string& field);

// The closest of `candidates` to `word` by edit distance, or "" when none is close.
std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates);

// An error at one of the parameters a variant was given (at the name, or at name.value:
// operating.speed is written there in a train) with that value as `shown` words it ("-10 µm"),
// not the SI number the variant holds; any other error as it is.
InputError AtParameterValue(const InputError& e, const std::vector<ParameterValue>& set,
                            const std::function<std::string(const ParameterValue&)>& shown);
// An axis value in the unit it is shown in: "-10 µm", "0.02" (no unit).
std::string AxisValueText(double shown_value, const std::string& unit);

}  // namespace gearnvh::config
