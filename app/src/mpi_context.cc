#include "mpi_context.h"

#include <cstdlib>

#ifdef GEARNVH_HAVE_MPI
// The C API only (OpenMPI otherwise pulls in its deprecated C++ bindings).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace gearnvh::app {

namespace {
int g_rank = 0, g_size = 1, g_node_size = 1;
bool g_initialized = false;

bool LaunchedByMpi() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"}) {
    if (std::getenv(v) != nullptr) return true;
  }
  return false;
}
}  // namespace

void MpiContext::Initialize(int* argc, char*** argv) {
#ifdef GEARNVH_HAVE_MPI
  if (!LaunchedByMpi()) return;
  int provided = 0;
  // Threads inside a rank never call MPI; only the main thread does.
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_initialized = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  MPI_Comm node;  // the ranks that can share memory with this one: its node's
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, g_rank, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &g_node_size);
  MPI_Comm_free(&node);
#else
  (void)argc;
  (void)argv;
#endif
}

void MpiContext::Finalize() {
#ifdef GEARNVH_HAVE_MPI
  if (g_initialized) MPI_Finalize();
  g_initialized = false;
#endif
}

int MpiContext::Rank() { return g_rank; }
int MpiContext::Size() { return g_size; }
int MpiContext::RanksOnNode() { return g_node_size; }

std::vector<std::string> MpiContext::GatherToRoot(const std::string& mine) {
#ifdef GEARNVH_HAVE_MPI
  if (g_initialized && g_size > 1) {
    int length = static_cast<int>(mine.size());
    std::vector<int> lengths(static_cast<size_t>(g_size)), offsets(static_cast<size_t>(g_size));
    MPI_Gather(&length, 1, MPI_INT, lengths.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
    std::string all;
    if (g_rank == 0) {
      int total = 0;
      for (int r = 0; r < g_size; ++r) {
        offsets[static_cast<size_t>(r)] = total;
        total += lengths[static_cast<size_t>(r)];
      }
      all.resize(static_cast<size_t>(total));
    }
    MPI_Gatherv(mine.data(), length, MPI_CHAR, all.data(), lengths.data(), offsets.data(), MPI_CHAR,
                0, MPI_COMM_WORLD);
    std::vector<std::string> out;
    if (g_rank == 0) {
      for (int r = 0; r < g_size; ++r) {
        out.push_back(all.substr(static_cast<size_t>(offsets[static_cast<size_t>(r)]),
                                 static_cast<size_t>(lengths[static_cast<size_t>(r)])));
      }
    }
    return out;
  }
#endif
  return {mine};
}

int MpiContext::BroadcastInt(int value) {
#ifdef GEARNVH_HAVE_MPI
  if (g_initialized && g_size > 1) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
  return value;
}

std::string MpiContext::BroadcastString(const std::string& value) {
#ifdef GEARNVH_HAVE_MPI
  if (g_initialized && g_size > 1) {
    int length = BroadcastInt(static_cast<int>(value.size()));
    std::string out = g_rank == 0 ? value : std::string(static_cast<size_t>(length), '\0');
    MPI_Bcast(out.data(), length, MPI_CHAR, 0, MPI_COMM_WORLD);
    return out;
  }
#endif
  return value;
}

std::string MpiContext::FirstNonEmpty(const std::string& mine) {
  std::string first;
  for (const std::string& s : GatherToRoot(mine)) {
    if (first.empty()) first = s;
  }
  return BroadcastString(first);
}

std::optional<MemoryLimit> AvailableMemoryOnEveryRank(int threads) {
  std::optional<MemoryLimit> limit;
  std::string error;
  try {
    limit = AvailableMemory(threads, MpiContext::RanksOnNode());
  } catch (const MemoryLimitVariableError& e) {
    error = e.what();
  }
  if (MpiContext::Active()) error = MpiContext::FirstNonEmpty(error);
  if (!error.empty()) throw MemoryLimitVariableError(error);
  return limit;
}

}  // namespace gearnvh::app
