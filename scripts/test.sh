#!/usr/bin/env bash
# Runs the whole gearnvh test suite (Catch2 and the Python module's pytest, through ctest).
#   bash scripts/test.sh             Release build in build/
#   bash scripts/test.sh --sanitize  the instrumented build in build-asan/ (clang, AddressSanitizer +
#                                    UndefinedBehaviorSanitizer); the Release-only tests are not
#                                    built there (docs/testing.md says which and why)
#   bash scripts/test.sh --sanitize --fuzz SECONDS
#                                    and the fuzzing campaign (scripts/fuzz.sh) beside the suite
# Each phase prints its seconds (install, build, tests).
set -euo pipefail
cd "$(dirname "$0")/.."
FUZZ_SECONDS=0
if [ "${1:-}" = "--sanitize" ]; then
  # shellcheck source=scripts/instrumented.sh
  source scripts/instrumented.sh
  [ "${2:-}" = "--fuzz" ] && FUZZ_SECONDS=${3:?--fuzz needs the seconds of the campaign}
fi
bash scripts/setup.sh
fuzz_pid=
if [ "$FUZZ_SECONDS" != 0 ]; then
  # The campaign is one process on one core: it runs beside the suite instead of after it.
  fuzz_log=$(mktemp)
  bash scripts/fuzz.sh --no-build "$FUZZ_SECONDS" > "$fuzz_log" 2>&1 &
  fuzz_pid=$!
fi
start=$(date +%s)
status=0
ctest --test-dir "${GEARNVH_BUILD_DIR:-build}" --output-on-failure -j "$(nproc)" || status=$?
echo "test: tests in ${GEARNVH_BUILD_DIR:-build} took $(( $(date +%s) - start )) s"
if [ -n "$fuzz_pid" ]; then
  fuzz_status=0
  wait "$fuzz_pid" || fuzz_status=$?
  tail -n 30 "$fuzz_log"
  rm -f "$fuzz_log"
  [ "$fuzz_status" = 0 ] || { echo "test: the fuzzing campaign failed ($fuzz_status)"; exit 1; }
fi
exit "$status"
