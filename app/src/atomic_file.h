// Writes a whole file or nothing: content goes to "<path>.tmp-<pid>" in the same directory, is
// flushed and then renamed over <path> (rename is atomic within a filesystem). Throws
// IoError (a std::runtime_error) naming the path on failure and removes the temporary.
#pragma once

#include <string>

namespace gearnvh::app {

void WriteFileAtomically(const std::string& path, const std::string& content);

}  // namespace gearnvh::app
