# Project-wide compile settings applied through one interface target.
add_library(gearnvh_options INTERFACE)
add_library(gearnvh::options ALIAS gearnvh_options)
target_compile_options(gearnvh_options INTERFACE -Wall -Wextra -Wpedantic)
if(GEARNVH_NATIVE AND NOT GEARNVH_FUZZ)
  target_compile_options(gearnvh_options INTERFACE -march=native)
  # GCC 12 reports false -Wmaybe-uninitialized inside its AVX-512 intrinsics when Eigen vectorises
  # (GCC PR 105593, fixed in 13). The non-native sanitizer build keeps the warning on.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(gearnvh_options INTERFACE -Wno-maybe-uninitialized)
  endif()
endif()
if(GEARNVH_SANITIZE OR GEARNVH_FUZZ)
  # The instrumented build (ASan + UBSan) serves the sanitizer suite and, with GEARNVH_FUZZ, the
  # fuzzer too. -O2 with line tables only: stack traces keep file:line (full -g is what made
  # RelWithDebInfo slow to compile), and Eigen's inlined kernels run about 1.4x faster than at
  # -O1 under ASan for about the same compile time (docs/testing.md).
  target_compile_options(gearnvh_options INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined -O2
    $<IF:$<CXX_COMPILER_ID:Clang>,-gline-tables-only,-g1>)
  target_link_options(gearnvh_options INTERFACE -fsanitize=address,undefined)
endif()

# libFuzzer coverage for a library the fuzzer drives (the loader, the model builders): only those
# are instrumented, so the sanitizer suite's solver runs pay no coverage callbacks.
function(gearnvh_fuzz_coverage target)
  if(GEARNVH_FUZZ)
    target_compile_options(${target} PRIVATE -fsanitize=fuzzer-no-link)
  endif()
endfunction()
