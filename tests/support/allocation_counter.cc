#include "support/allocation_counter.h"

#include <cstdlib>
#include <new>

namespace gearnvh::testing {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
}  // namespace gearnvh::testing

// Global replacements: count, then allocate with malloc.
void* operator new(std::size_t size) {
  if (gearnvh::testing::g_counting) ++gearnvh::testing::g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
