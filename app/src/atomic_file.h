// Writes a whole file or nothing: content goes to "<path>.tmp-<pid>" in the same directory, is
// flushed and then renamed over <path> (rename is atomic within a filesystem). Throws
// IoError (a std::runtime_error) naming the path on failure and removes the temporary.
#pragma once

#include <cstdio>
#include <functional>
#include <string>

namespace gearnvh::app {

void WriteFileAtomically(const std::string& path, const std::string& content);
// The same with the content written by `write` as it goes (a file too large to hold as a string);
// a write error it leaves on the stream (ferror) fails the whole file.
void WriteFileAtomically(const std::string& path, const std::function<void(std::FILE*)>& write);

}  // namespace gearnvh::app
