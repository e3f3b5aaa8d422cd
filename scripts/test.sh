#!/usr/bin/env bash
# Runs the whole gearnvh test suite (Catch2 and the Python module's pytest, through ctest).
#   bash scripts/test.sh             Release build in build/
#   bash scripts/test.sh --sanitize  AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan/
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  export GEARNVH_BUILD_DIR=build-asan
  # No Python module here: an ASan-instrumented extension needs libasan preloaded into the Python
  # interpreter (LD_PRELOAD), which sanitizes CPython itself; the module's C++ is the library the
  # Catch2 suite already runs under the sanitizers.
  export GEARNVH_CMAKE_ARGS="-DGEARNVH_SANITIZE=ON -DGEARNVH_NATIVE=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEARNVH_BUILD_PYTHON=OFF"
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  # Graphics libraries (Mesa, X11, VTK singletons) keep allocations until exit by design.
  export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/lsan.supp:print_suppressions=0}
fi
bash scripts/setup.sh
ctest --test-dir "${GEARNVH_BUILD_DIR:-build}" --output-on-failure -j "$(nproc)"
