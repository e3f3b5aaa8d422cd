#include "atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

#include "command_errors.h"

namespace gearnvh::app {

void WriteFileAtomically(const std::string& path, const std::function<void(std::FILE*)>& write) {
  const std::string tmp = path + ".tmp-" + std::to_string(::getpid());
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) {
    const std::string reason = std::strerror(errno);
    throw IoError("cannot write " + path + ": " + reason, reason);
  }
  auto discard = [&tmp] {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
  };
  std::error_code write_error;  // fmt::print's report of a failed write, with its errno
  try {
    write(f);
  } catch (const std::system_error& e) {
    write_error = e.code();
    if (!write_error) write_error = std::make_error_code(std::errc::io_error);
  } catch (...) {  // anything else (std::bad_alloc while formatting): no file, the error as it is
    std::fclose(f);
    discard();
    throw;
  }
  const bool ok =
      !write_error && std::ferror(f) == 0 && std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed || std::rename(tmp.c_str(), path.c_str()) != 0) {
    // The failed write's own error: errno may since have been set by the calls after it.
    const std::string reason = write_error ? write_error.message() : std::strerror(errno);
    discard();
    throw IoError("cannot write " + path + ": " + reason, reason);
  }
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  WriteFileAtomically(
      path, [&content](std::FILE* f) { std::fwrite(content.data(), 1, content.size(), f); });
}

}  // namespace gearnvh::app
