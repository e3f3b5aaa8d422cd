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
build_dir=${GEARNVH_BUILD_DIR:-build}
ctest_log=$(mktemp)
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" 2>&1 | tee "$ctest_log" ||
  status=$?
echo "test: tests in $build_dir took $(( $(date +%s) - start )) s"
if [ -n "$fuzz_pid" ]; then
  fuzz_status=0
  wait "$fuzz_pid" || fuzz_status=$?
  tail -n 30 "$fuzz_log"
  rm -f "$fuzz_log"
  [ "$fuzz_status" = 0 ] || { echo "test: the fuzzing campaign failed ($fuzz_status)"; exit 1; }
fi
if [ "$status" != 0 ]; then
  # The failures' own output once more, at the end of the log where a CI summary shows it (in the
  # middle it is cut, and the fuzzing campaign's tail follows it).
  echo "test: what the failed tests printed (first 120 lines of each):"
  awk '/\*\*\*(Failed|Exception|Timeout)/ { p = 1; n = 0 }
       p && /^ +Start +[0-9]+:/ { p = 0 }
       p { print; if (++n >= 120) p = 0 }' "$ctest_log"
  if [ -n "${ASAN_OPTIONS:-}" ]; then
    # Under the sanitizers a test that aborted once is run again, alone: one that passes then is
    # named as flaky (docs/testing.md) and does not fail the suite; one that fails again does.
    echo "test: the failed tests once more, one at a time:"
    if ctest --test-dir "$build_dir" --rerun-failed --output-on-failure -j 1; then
      echo "test: FLAKY under the sanitizers (failed once, passed alone):"
      grep -E '\*\*\*(Failed|Exception|Timeout)' "$ctest_log" || true
      status=0
    fi
  fi
fi
rm -f "$ctest_log"
exit "$status"
