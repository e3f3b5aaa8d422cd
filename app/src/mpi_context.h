// MPI for the scale-out commands (atlas, sweep): initialised only when the process was started by
// an MPI launcher (mpirun / srun set OMPI_COMM_WORLD_SIZE, PMI_SIZE or PMIX_RANK), so a plain
// `gearnvh atlas` never touches MPI. Without MPI support compiled in, or outside a launcher, this
// is a single rank 0 of 1.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "gearnvh/analysis/run_memory.h"

namespace gearnvh::app {

class MpiContext {
 public:
  // Initialises MPI when launched by an MPI launcher; call once at the start of main().
  static void Initialize(int* argc, char*** argv);
  // Finalises MPI if it was initialised; call before main() returns.
  static void Finalize();
  static int Rank();
  static int Size();
  static bool Active() { return Size() > 1; }
  // The ranks on this rank's node (sharing its memory), this one included; 1 without MPI.
  static int RanksOnNode();
  // Rank 0 receives every rank's string, in rank order; other ranks receive an empty vector.
  static std::vector<std::string> GatherToRoot(const std::string& mine);
  // Rank 0's value on every rank.
  static int BroadcastInt(int value);
  static std::string BroadcastString(const std::string& value);
  // The first non-empty of the ranks' strings, in rank order, on every rank ("" when all are).
  static std::string FirstNonEmpty(const std::string& mine);
};

// AvailableMemory for the ranks of one MPI run (each with its ranks on the node sharing): a
// malformed GEARNVH_MEMORY_LIMIT on any rank is the same MemoryLimitVariableError on every rank
// (the first rank's), so no rank is left waiting in a later collective for one that threw.
std::optional<MemoryLimit> AvailableMemoryOnEveryRank(int threads);

}  // namespace gearnvh::app
