// Gearbox files are UTF-8: anything else is an input error at its line, before YAML parsing (so no
// invalid byte sequence reaches a name, a report page or a JSON document).
#pragma once

#include <string>

namespace gearnvh::config {

// Throws InputError (line, byte offset, the offending bytes in hex) for the first byte sequence
// that is not well-formed UTF-8 (overlong forms, surrogates and values above U+10FFFF included),
// and for a control character YAML does not allow (C0 other than tab, LF, CR; DEL).
void RequireValidUtf8(const std::string& text, const std::string& source);

// The byte offset of the first control character of `text` (C0 including tab and line feed, DEL,
// C1 U+0080-U+009F), std::string::npos when it has none. YAML escapes ("\x07", "\0") put them
// into a scalar that the file itself may not hold.
size_t ControlCharacterAt(const std::string& text);

}  // namespace gearnvh::config
