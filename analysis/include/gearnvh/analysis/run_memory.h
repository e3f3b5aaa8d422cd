// The memory a run will hold, estimated before it starts from the same numbers the recording
// reserves (solver/run_recording.h, PlanRecording), and checked against what the machine has
// (docs/cli.md, "Memory"): refused above the limit, a warning above kMemoryWarningBytes or half
// the limit.
#pragma once

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace gearnvh {

struct MemoryPart {
  std::string name;  // "recorded samples", "event log", "TE spectrum", ...
  size_t bytes = 0;
};

struct RunMemory {
  std::vector<MemoryPart> parts;  // the parts that grow with the recorded cycles
  long recorded_samples = 0;      // uniform samples kept, for a command's own copies of them
  size_t bearing_rows = 0;        // bearing force rows kept per sample (a train's bearings x 3)
  size_t bytes() const;
  // "1.3 GiB (recorded samples 256 MiB, event log 24 MiB, TE spectrum 144 MiB)"
  std::string Describe() const;
};

// "512 MiB", "1.3 GiB", "12 KiB", "100 B".
std::string BytesText(size_t bytes);

// The remedy a refusal names unless the command has its own ("or --jobs", ...).
inline constexpr const char* kFewerCycles = "fewer recorded cycles need less";

// A run estimated above this is warned about (as is one above half the limit).
constexpr size_t kMemoryWarningBytes = size_t{1} << 30;

// A malformed GEARNVH_MEMORY_LIMIT: invalid input (exit 1) that names the environment variable.
class MemoryLimitVariableError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct MemoryLimit {
  size_t bytes = 0;
  std::string source;  // "MemAvailable in /proc/meminfo", "GEARNVH_MEMORY_LIMIT", ...
};

// What the estimate leaves out and the limit keeps back for it (docs/cli.md, "Memory"): what the
// process allocates after the check besides the parts (result documents, output buffers, the
// allocator's fragmentation); VmSize grew at most 1 MiB more than the estimate in `simulate` of
// the examples.
constexpr size_t kUnestimatedBytes = size_t{16} << 20;
// The address space a worker thread started after the check takes under ulimit -v: its stack
// (8 MiB) and its malloc arena (glibc reserves 64 MiB per arena), whether used or not.
constexpr size_t kThreadAddressSpaceBytes = size_t{72} << 20;

// The memory a run may take, read at the check (after the model and its tables exist): the
// environment variable GEARNVH_MEMORY_LIMIT (a whole number of bytes; to hold gearnvh below what
// the machine has, and for tests) when set, else the smaller of MemAvailable of /proc/meminfo and
// the address space left under ulimit -v (RLIMIT_AS less the process's VmSize), each less
// kUnestimatedBytes, the latter also less kThreadAddressSpaceBytes for each of the `threads` the
// run starts after the check; nullopt when none exists. The `sharing` processes of one run on
// this machine (MPI ranks on the node) divide GEARNVH_MEMORY_LIMIT and MemAvailable. A malformed
// GEARNVH_MEMORY_LIMIT is a MemoryLimitVariableError naming the environment variable.
std::optional<MemoryLimit> AvailableMemory(int threads = 0, int sharing = 1);

// The rule an estimate above `limit` breaks ("the run would hold about ..., more than the ... of
// memory available (...); `remedy`"), "" when it fits.
std::string MemoryRefusal(const RunMemory& need, const std::optional<MemoryLimit>& limit,
                          const std::string& remedy = kFewerCycles);

// Refuses a run whose estimate exceeds `limit`: InputError at `option` (where the user set the
// recorded cycles: --cycles or analysis.cycles) with `value`, naming the estimate by part and the
// limit, and `remedy`. Returns the one-line warning for an estimate above kMemoryWarningBytes or
// half the limit, else "".
std::string CheckRunMemory(const RunMemory& need, const std::optional<MemoryLimit>& limit,
                           const std::string& option, const std::string& value,
                           const std::string& remedy = kFewerCycles);

}  // namespace gearnvh
