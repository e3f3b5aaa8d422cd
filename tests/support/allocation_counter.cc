#include "support/allocation_counter.h"

#include <cstdlib>
#include <new>

#include "support/sanitizer.h"

namespace gearnvh::testing {
std::atomic<long> g_allocations{0};
std::atomic<bool> g_counting{false};
}  // namespace gearnvh::testing

// Global replacements of every operator new/delete form (plain, array, nothrow, aligned), so that
// no allocation made by one implementation is released by another (ASan checks that).
// Eigen's heap (MatrixXd temporaries, resizing) calls std::malloc directly, not operator new: the
// test binary interposes malloc, calloc and realloc (glibc's own entry points do the work) so those
// are counted too. Not under a sanitizer, whose runtime interposes them itself.
#if defined(__GLIBC__) && !defined(GEARNVH_UNDER_ASAN)
#define GEARNVH_COUNT_MALLOC 1
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* p, std::size_t size);
void* malloc(std::size_t size) {
  if (gearnvh::testing::g_counting) ++gearnvh::testing::g_allocations;
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  if (gearnvh::testing::g_counting) ++gearnvh::testing::g_allocations;
  return __libc_calloc(count, size);
}
void* realloc(void* p, std::size_t size) {
  if (gearnvh::testing::g_counting) ++gearnvh::testing::g_allocations;
  return __libc_realloc(p, size);
}
}
#endif

namespace {
void* Allocate(std::size_t size, std::size_t alignment) {
#ifndef GEARNVH_COUNT_MALLOC
  if (gearnvh::testing::g_counting) ++gearnvh::testing::g_allocations;
#endif
  if (size == 0) size = 1;
  if (alignment <= alignof(std::max_align_t)) return std::malloc(size);
  const std::size_t rounded = (size + alignment - 1) / alignment * alignment;
  return std::aligned_alloc(alignment, rounded);
}
void* AllocateOrThrow(std::size_t size, std::size_t alignment) {
  if (void* p = Allocate(size, alignment)) return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) { return AllocateOrThrow(n, 0); }
void* operator new[](std::size_t n) { return AllocateOrThrow(n, 0); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return Allocate(n, 0); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return Allocate(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) {
  return AllocateOrThrow(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return AllocateOrThrow(n, static_cast<std::size_t>(a));
}
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return Allocate(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return Allocate(n, static_cast<std::size_t>(a));
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
