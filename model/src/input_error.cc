#include "gearnvh/model/input_error.h"

#include <fmt/format.h>

#include <algorithm>
#include <numbers>
#include <string_view>

namespace gearnvh {

namespace {

// How the library shows lengths and angles: as gear drawings and gear files write them.
DisplayUnit LibraryUnit(InputError::Dimension dimension) {
  return dimension == InputError::Dimension::kLength ? DisplayUnit{"mm", 1e3}
                                                     : DisplayUnit{"deg", 180.0 / std::numbers::pi};
}

// Text as a message shows it: a control character escaped ("\x07"; a terminal or a page would
// act on it, NUL included), and cut after `limit` characters with its size in bytes (a 1 MB value
// is not echoed whole). Cuts fall between UTF-8 sequences.
std::string Shown(std::string_view text, size_t limit) {
  std::string out;
  size_t i = 0;
  for (size_t shown = 0; i < text.size() && shown < limit; ++shown) {
    const auto c = static_cast<unsigned char>(text[i]);
    const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
    if (c < 0x20 || c == 0x7F) {
      out += fmt::format("\\x{:02X}", c);
      ++i;
    } else if (c == 0xC2 && next >= 0x80 && next <= 0x9F) {  // C1 controls, U+0080-U+009F
      out += fmt::format("\\u{:04X}", next);
      i += 2;
    } else {
      size_t n = c < 0x80 ? 1 : c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 1;
      n = std::min(n, text.size() - i);
      out.append(text.substr(i, n));
      i += n;
    }
  }
  if (i < text.size()) out += fmt::format("… ({} bytes)", text.size());
  return out;
}

// Characters shown of an error's path, value and rule.
constexpr size_t kShownPath = 200, kShownValue = 60, kShownRule = 2000;

}  // namespace

InputError::InputError(std::string path, int line, Text value, Text rule, std::string source,
                       std::string written_value)
    : std::runtime_error(Format(
          source, line, path, written_value.empty() ? Render(value) : written_value, Render(rule))),
      path_(std::move(path)),
      line_(line),
      value_text_(std::move(value)),
      rule_text_(std::move(rule)),
      written_value_(std::move(written_value)),
      value_(written_value_.empty() ? Render(value_text_) : written_value_),
      rule_(Render(rule_text_)),
      source_(std::move(source)) {}

InputError InputError::Located(int line, const std::string& written_value,
                               const std::string& source, const UnitOf& unit_of) const {
  auto resolve = [&](Text text) {
    if (!unit_of) return text;
    for (Quantity& q : text.quantities) {
      if (!q.shown_in) q.shown_in = unit_of(q.unit_path.empty() ? path_ : q.unit_path, q.dimension);
    }
    return text;
  };
  return InputError(path_, line, resolve(value_text_), resolve(rule_text_), source,
                    written_value.empty() ? written_value_ : written_value);
}

InputError InputError::Renamed(
    const std::function<std::string(const std::string&)>& path_of,
    const std::function<std::string(const std::string&)>& rule_of) const {
  auto rename = [&](Text text) {
    for (Quantity& q : text.quantities) {
      if (!q.unit_path.empty()) q.unit_path = path_of(q.unit_path);
    }
    return text;
  };
  Text rule = rename(rule_text_);
  rule.form = rule_of(rule.form);
  return InputError(path_of(path_), line_, rename(value_text_), rule, source_, written_value_);
}

std::string InputError::Render(const Text& text) {
  if (text.quantities.empty()) return text.form;
  std::string out;
  size_t next = 0;
  DisplayUnit unit;  // of the quantity shown last
  const std::string_view form = text.form;
  for (size_t at = 0; at < form.size();) {
    const auto placeholder = [&](std::string_view p) { return form.substr(at, p.size()) == p; };
    const bool with_unit = placeholder("{}"), number = placeholder("{#}");
    if ((with_unit || number) && next < text.quantities.size()) {
      const Quantity& q = text.quantities[next++];
      unit = q.shown_in.value_or(LibraryUnit(q.dimension));
      out += fmt::format("{:.{}g}", q.si * unit.per_si, q.digits);
      if (with_unit) out += " " + unit.symbol;
      at += with_unit ? 2 : 3;
    } else if (placeholder("{unit}")) {
      out += unit.symbol;
      at += 6;
    } else {
      out += form[at++];
    }
  }
  return out;
}

std::string InputError::Format(const std::string& source, int line, const std::string& path,
                               const std::string& value, const std::string& rule) {
  std::string out;
  if (!source.empty()) out += source + ":";
  if (line > 0) out += std::to_string(line) + ":";
  if (!out.empty()) out += " ";
  out += path.empty() ? std::string("(document)") : Shown(path, kShownPath);
  out += ": " + Shown(rule, kShownRule);
  if (!value.empty()) out += ", got " + Shown(value, kShownValue);
  return out;
}

std::string MessageNumber(double v) { return fmt::format("{:.6g}", v); }

}  // namespace gearnvh
