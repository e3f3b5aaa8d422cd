// InputError: the one exception type for bad user input (docs/design.md §1, "three kinds of failure").
//
// It carries the YAML path of the offending value, the source line (1-based, 0 when unknown),
// the value as written and the rule it broke, so the message reads
//   file.yaml:12: mesh.backlash: must be > 0, got -1e-5
#pragma once

#include <stdexcept>
#include <string>

namespace gearnvh {

class InputError : public std::runtime_error {
 public:
  InputError(std::string path, int line, std::string value, std::string rule,
             std::string source = {})
      : std::runtime_error(Format(source, line, path, value, rule)),
        path_(std::move(path)),
        line_(line),
        value_(std::move(value)),
        rule_(std::move(rule)),
        source_(std::move(source)) {}

  const std::string& path() const { return path_; }
  int line() const { return line_; }
  const std::string& value() const { return value_; }
  const std::string& rule() const { return rule_; }
  const std::string& source() const { return source_; }

  // The same error attributed to a source file (the loader knows it, the parser may not).
  InputError WithSource(const std::string& source) const {
    return InputError(path_, line_, value_, rule_, source);
  }

 private:
  static std::string Format(const std::string& source, int line, const std::string& path,
                            const std::string& value, const std::string& rule) {
    std::string out;
    if (!source.empty()) out += source + ":";
    if (line > 0) out += std::to_string(line) + ":";
    if (!out.empty()) out += " ";
    out += path.empty() ? std::string("(document)") : path;
    out += ": " + rule;
    if (!value.empty()) out += ", got " + value;
    return out;
  }

  std::string path_;
  int line_;
  std::string value_;
  std::string rule_;
  std::string source_;
};

}  // namespace gearnvh
