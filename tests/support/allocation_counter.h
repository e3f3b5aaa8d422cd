// Counts global operator new calls while an AllocationCounter is alive (test helper).
// The replacement operators are defined in allocation_counter.cc, linked into the test binary.
#pragma once

#include <atomic>
#include <cstddef>

namespace gearnvh::testing {

extern std::atomic<long> g_allocations;
extern std::atomic<bool> g_counting;

class AllocationCounter {
 public:
  AllocationCounter() {
    g_allocations = 0;
    g_counting = true;
  }
  ~AllocationCounter() { g_counting = false; }
  long count() const { return g_allocations.load(); }
};

}  // namespace gearnvh::testing
