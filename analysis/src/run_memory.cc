#include "gearnvh/analysis/run_memory.h"

#include <fmt/format.h>
#include <sys/resource.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "gearnvh/model/input_error.h"

namespace gearnvh {

size_t RunMemory::bytes() const {
  size_t total = 0;
  for (const MemoryPart& p : parts) total += p.bytes;
  return total;
}

std::string RunMemory::Describe() const {
  std::string listed;
  for (const MemoryPart& p : parts) {
    if (p.bytes == 0) continue;
    listed += (listed.empty() ? "" : ", ") + p.name + " " + BytesText(p.bytes);
  }
  return BytesText(bytes()) + (listed.empty() ? "" : " (" + listed + ")");
}

std::string BytesText(size_t bytes) {
  constexpr const char* kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  auto value = static_cast<double>(bytes);
  size_t unit = 0;
  while (value >= 1024.0 && unit + 1 < std::size(kUnits)) {
    value /= 1024.0;
    ++unit;
  }
  return unit == 0 || value >= 100.0 ? fmt::format("{:.0f} {}", value, kUnits[unit])
                                     : fmt::format("{:.3g} {}", value, kUnits[unit]);
}

namespace {

// A "Key:   12345 kB" line of a /proc file in bytes; nullopt where there is none.
std::optional<size_t> ProcKib(const char* path, const std::string& key) {
  std::ifstream file(path);
  std::string line;
  while (std::getline(file, line)) {
    if (line.rfind(key, 0) != 0) continue;
    std::istringstream fields(line.substr(key.size()));
    size_t kib = 0;
    if (fields >> kib) return kib * 1024;
  }
  return std::nullopt;
}

std::optional<size_t> MemAvailable() { return ProcKib("/proc/meminfo", "MemAvailable:"); }

// The address space left under the process's limit (ulimit -v): RLIMIT_AS less VmSize of
// /proc/self/status; nullopt when there is no limit.
std::optional<size_t> AddressSpaceLeft() {
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return std::nullopt;
  const size_t used = ProcKib("/proc/self/status", "VmSize:").value_or(0);
  const auto cap = static_cast<size_t>(limit.rlim_cur);
  return cap > used ? cap - used : 0;
}

size_t Less(size_t bytes, size_t reserved) { return bytes > reserved ? bytes - reserved : 0; }

// ", shared by 2 processes on this node", "" for one.
std::string SharedBy(int sharing) {
  return sharing > 1 ? fmt::format(", shared by {} processes on this node", sharing) : "";
}

}  // namespace

std::optional<MemoryLimit> AvailableMemory(int threads, int sharing) {
  constexpr const char* kVariable = "GEARNVH_MEMORY_LIMIT";
  const auto share = static_cast<size_t>(std::max(sharing, 1));
  if (const char* text = std::getenv(kVariable); text != nullptr) {
    const std::string s = text;
    size_t bytes = 0;
    const auto [stop, error] = std::from_chars(s.data(), s.data() + s.size(), bytes);
    const bool whole = !s.empty() && stop == s.data() + s.size();
    if (whole && error == std::errc::result_out_of_range) {
      throw MemoryLimitVariableError(
          fmt::format("the environment variable {} is {}: too large, at most {} bytes", kVariable,
                      s, std::numeric_limits<size_t>::max()));
    }
    if (!whole || error != std::errc()) {
      throw MemoryLimitVariableError(fmt::format(
          "the environment variable {} is '{}': it must be a whole number of bytes", kVariable, s));
    }
    return MemoryLimit{bytes / share, kVariable + SharedBy(sharing)};
  }
  std::optional<MemoryLimit> out;
  if (const std::optional<size_t> available = MemAvailable()) {
    out = MemoryLimit{Less(*available / share, kUnestimatedBytes),
                      "MemAvailable in /proc/meminfo" + SharedBy(sharing) + ", less " +
                          BytesText(kUnestimatedBytes) + " kept back"};
  }
  if (std::optional<size_t> left = AddressSpaceLeft()) {
    const size_t reserved =
        kUnestimatedBytes + static_cast<size_t>(std::max(threads, 0)) * kThreadAddressSpaceBytes;
    *left = Less(*left, reserved);
    if (!out || *left < out->bytes) {
      out = MemoryLimit{*left, "the address space left under ulimit -v, less " +
                                   BytesText(reserved) + " kept back"};
    }
  }
  return out;
}

std::string MemoryRefusal(const RunMemory& need, const std::optional<MemoryLimit>& limit,
                          const std::string& remedy) {
  if (!limit || need.bytes() <= limit->bytes) return "";
  return fmt::format("the run would hold about {}, more than the {} of memory available ({}); {}",
                     need.Describe(), BytesText(limit->bytes), limit->source, remedy);
}

std::string CheckRunMemory(const RunMemory& need, const std::optional<MemoryLimit>& limit,
                           const std::string& option, const std::string& value,
                           const std::string& remedy) {
  if (std::string rule = MemoryRefusal(need, limit, remedy); !rule.empty()) {
    throw InputError(option, 0, value, std::move(rule));
  }
  const size_t bytes = need.bytes();
  const size_t warn_above =
      limit ? std::min(kMemoryWarningBytes, limit->bytes / 2) : kMemoryWarningBytes;
  if (bytes <= warn_above) return "";
  return fmt::format(
      "{} {}: the run will hold about {}{}", option, value, need.Describe(),
      limit ? fmt::format(" of the {} available ({})", BytesText(limit->bytes), limit->source)
            : "");
}

}  // namespace gearnvh
