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
if(GEARNVH_SANITIZE)
  target_compile_options(gearnvh_options INTERFACE
    -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  target_link_options(gearnvh_options INTERFACE -fsanitize=address,undefined)
endif()
if(GEARNVH_FUZZ)
  # Instrument every library for coverage; the fuzzer executable adds the libFuzzer main.
  target_compile_options(gearnvh_options INTERFACE
    -fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer -g)
  target_link_options(gearnvh_options INTERFACE -fsanitize=address,undefined)
endif()
