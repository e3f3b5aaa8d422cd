#include "png_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>

namespace gearnvh::render {

RenderStatus WritePng(const std::string& png_path, const unsigned char* bytes, size_t size) {
  const std::filesystem::path target(png_path);
  std::random_device rd;
  const std::filesystem::path tmp =
      target.parent_path() / ("." + target.filename().string() + ".tmp" + std::to_string(rd()));
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) {
    const int error = errno;
    return {false, "could not write " + png_path + ": " + std::strerror(error), {}, error};
  }
  bool ok =
      std::fwrite(bytes, 1, size, f) == size && std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  int error = ok ? 0 : errno;
  if (std::fclose(f) != 0 && ok) {
    ok = false;
    error = errno;
  }
  if (ok && std::rename(tmp.c_str(), target.c_str()) != 0) {
    ok = false;
    error = errno;
  }
  if (!ok) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    return {false, "could not write " + png_path + ": " + std::strerror(error), {}, error};
  }
  return {};
}

}  // namespace gearnvh::render
