// InputError: the one exception type for bad user input (docs/design.md §1, "three kinds of
// failure").
//
// It carries the YAML path of the offending value, the source line (1-based, 0 when unknown),
// the value as written and the rule it broke, so the message reads
//   file.yaml:12: mesh.backlash: must be > 0, got -1e-5
//
// A rule on a length or an angle keeps its numbers in SI (Quantity) rather than as text: the
// library shows them in mm and deg, and the app, which knows the unit the user wrote at each YAML
// path, shows them in that unit (Located). The library thus never needs to know the file.
#pragma once

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

// DisplayUnit (the unit a quantity is shown in to the user) lives with the spec for now.
#include "gearnvh/model/gearbox_spec.h"

namespace gearnvh {

class InputError : public std::runtime_error {
 public:
  enum class Dimension { kLength, kAngle };

  // A length or an angle of a message, in SI (m, rad), shown with `digits` significant digits in
  // the unit written at `unit_path` ("" for the error's own path) once Located knows it
  // (`shown_in`), in mm or deg until then.
  struct Quantity {
    double si = 0.0;
    Dimension dimension = Dimension::kLength;
    std::string unit_path;
    int digits = 6;
    std::optional<DisplayUnit> shown_in;
  };
  static Quantity Length(double m, std::string unit_path = {}, int digits = 6) {
    return Of(m, Dimension::kLength, std::move(unit_path), digits);
  }
  static Quantity Angle(double rad, std::string unit_path = {}, int digits = 6) {
    return Of(rad, Dimension::kAngle, std::move(unit_path), digits);
  }

  // A message part: `form` as it is, or, when `quantities` are given, `form` with "{}" replaced by
  // the next quantity with its unit ("2 mm"), "{#}" by its number alone and "{unit}" by the unit
  // of the quantity before ("in [{#}, {}]" -> "in [0.05, 100 mm]").
  struct Text {
    // A plain text converts, so every rule written as text stays as it is.
    Text(std::string plain = {}) : form(std::move(plain)) {}  // NOLINT(google-explicit-constructor)
    Text(const char* plain) : form(plain) {}                  // NOLINT(google-explicit-constructor)
    Text(std::string form_with_quantities, std::vector<Quantity> values)
        : form(std::move(form_with_quantities)), quantities(std::move(values)) {}
    std::string form;
    std::vector<Quantity> quantities;
  };

  // The unit to show a quantity of `dimension` written at `path` in; nullopt: mm or deg.
  using UnitOf =
      std::function<std::optional<DisplayUnit>(const std::string& path, Dimension dimension)>;

  InputError(std::string path, int line, Text value, Text rule, std::string source = {})
      : InputError(std::move(path), line, std::move(value), std::move(rule), std::move(source),
                   std::string()) {}

  const std::string& path() const { return path_; }
  int line() const { return line_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }
  const std::string& source() const { return source_; }

  // The same error attributed to a source file (the loader knows it, the parser may not).
  InputError WithSource(const std::string& source) const {
    return InputError(path_, line_, value_text_, rule_text_, source, written_value_);
  }

  // The same error located in its file: the line, the value as written ("" keeps the value) and
  // the units its lengths and angles were written in.
  InputError Located(int line, const std::string& written_value, const std::string& source,
                     const UnitOf& unit_of) const;

  // The same error with its paths (its own and those its quantities take their units from) renamed
  // by `path_of` and its rule's text rewritten by `rule_of` (a train restating a pair's rule).
  InputError Renamed(const std::function<std::string(const std::string&)>& path_of,
                     const std::function<std::string(const std::string&)>& rule_of) const;

 private:
  InputError(std::string path, int line, Text value, Text rule, std::string source,
             std::string written_value);

  static Quantity Of(double si, Dimension dimension, std::string unit_path, int digits) {
    Quantity q;
    q.si = si;
    q.dimension = dimension;
    q.unit_path = std::move(unit_path);
    q.digits = digits;
    return q;
  }
  // `text` with its quantities in their units.
  static std::string Render(const Text& text);
  static std::string Format(const std::string& source, int line, const std::string& path,
                            const std::string& value, const std::string& rule);

  std::string path_;
  int line_;
  Text value_text_, rule_text_;
  std::string written_value_;  // the value as written in the file, when known
  std::string value_;
  std::string rule_;
  std::string source_;
};

// A number in a message or a rule: six significant digits (printf %.6g: 0.001, 2.5e+08).
std::string MessageNumber(double v);

}  // namespace gearnvh
