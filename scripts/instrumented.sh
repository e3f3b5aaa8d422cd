# Sourced by scripts/test.sh --sanitize and scripts/fuzz.sh: the one instrumented build in
# build-asan/ (clang, ASan + UBSan at -O2, libFuzzer coverage on the loader and model libraries)
# that serves both the sanitizer suite and the fuzzer (docs/testing.md).
export GEARNVH_BUILD_DIR=build-asan
# No Python module here: an ASan-instrumented extension needs libasan preloaded into the Python
# interpreter (LD_PRELOAD), which sanitizes CPython itself; the module's C++ is the library the
# Catch2 suite already runs under the sanitizers.
export GEARNVH_CMAKE_ARGS="-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DGEARNVH_SANITIZE=ON -DGEARNVH_FUZZ=ON -DGEARNVH_NATIVE=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEARNVH_BUILD_PYTHON=OFF ${GEARNVH_CMAKE_ARGS:-}"
# intercept_tls_get_addr=0: clang 14's __tls_get_addr interceptor takes a dynamic TLS block that
# happens to start 16 bytes past a page boundary for a pre-2.25 glibc header and records the two
# words before it as the block; LeakSanitizer's tracer then reads that garbage at exit and dies
# ("Tracer caught signal 11"), deterministically for a given binary and machine (docs/testing.md).
# Appended to options set beforehand too.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}:intercept_tls_get_addr=0"
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# Graphics libraries (Mesa, X11, VTK singletons) keep allocations until exit by design.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/tests/lsan.supp:print_suppressions=0}
