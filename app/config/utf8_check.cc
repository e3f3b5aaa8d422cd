#include "utf8_check.h"

#include <fmt/format.h>

#include "gearnvh/model/input_error.h"

namespace gearnvh::config {

namespace {

// Length of the well-formed UTF-8 sequence at text[i] (RFC 3629, Unicode table 3-7), 0 if none.
size_t SequenceLength(const std::string& text, size_t i) {
  auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char b0 = byte(i);
  if (b0 < 0x80) return 1;
  size_t n = 0;
  unsigned char lo = 0x80, hi = 0xBF;
  if (b0 >= 0xC2 && b0 <= 0xDF) {
    n = 2;
  } else if (b0 >= 0xE0 && b0 <= 0xEF) {
    n = 3;
    if (b0 == 0xE0) lo = 0xA0;  // overlong
    if (b0 == 0xED) hi = 0x9F;  // surrogates
  } else if (b0 >= 0xF0 && b0 <= 0xF4) {
    n = 4;
    if (b0 == 0xF0) lo = 0x90;  // overlong
    if (b0 == 0xF4) hi = 0x8F;  // above U+10FFFF
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return n;
}

}  // namespace

void RequireValidUtf8(const std::string& text, const std::string& source) {
  int line = 1;
  size_t line_start = 0;
  for (size_t i = 0; i < text.size();) {
    const size_t n = SequenceLength(text, i);
    if (n == 0) {
      std::string bytes;
      for (size_t k = i; k < std::min(text.size(), i + 4); ++k) {
        bytes += fmt::format("{}\\x{:02X}", bytes.empty() ? "" : "", static_cast<unsigned char>(text[k]));
      }
      throw InputError("", line, "\"" + bytes + "\" at column " + std::to_string(i - line_start + 1),
                       "the file must be UTF-8 text", source);
    }
    // YAML's printable set has no other C0 control (nor DEL); yaml-cpp reads a leading NUL as a
    // UTF-16 byte-order guess and a later one as the end of the text.
    const auto c = static_cast<unsigned char>(text[i]);
    if ((c < 0x20 && c != '\t' && c != '\n' && c != '\r') || c == 0x7F) {
      throw InputError("", line, fmt::format("\"\\x{:02X}\" at column {}", c, i - line_start + 1),
                       "the file must be text: YAML allows no control characters other than tab, "
                       "line feed and carriage return",
                       source);
    }
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
    i += n;
  }
}

size_t ControlCharacterAt(const std::string& text) {
  for (size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
    if (c < 0x20 || c == 0x7F || (c == 0xC2 && next >= 0x80 && next <= 0x9F)) return i;
  }
  return std::string::npos;
}

}  // namespace gearnvh::config
