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
SANITIZE=0
if [ "${1:-}" = "--sanitize" ]; then
  SANITIZE=1
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
trap 'rm -f "$ctest_log"' EXIT
ctest --test-dir "$build_dir" --output-on-failure -j "$(nproc)" 2>&1 | tee "$ctest_log" ||
  status=$?
echo "test: tests in $build_dir took $(( $(date +%s) - start )) s"
fuzz_status=0
if [ -n "$fuzz_pid" ]; then
  wait "$fuzz_pid" || fuzz_status=$?
  tail -n 30 "$fuzz_log"
  rm -f "$fuzz_log"
fi
if [ "$status" != 0 ]; then
  # The failures' own output once more, at the end of the log where a CI summary shows it (in the
  # middle it is cut, and the fuzzing campaign's tail follows it).
  echo "test: what the failed tests printed (up to 120 lines of each):"
  awk '/\*\*\*(Failed|Exception|Timeout)/ { p = 1; n = 0; print; next }
       p && (/^ +Start +[0-9]+:/ || /^ *[0-9]+\/[0-9]+ Test +#/) { p = 0 }
       p { print; if (++n >= 120) p = 0 }' "$ctest_log"
  # Under the sanitizers a test that failed without a sanitizer report and without a timeout is
  # run again, alone, up to three times: passing then, it is named FLAKY and does not fail the
  # suite (docs/testing.md). A sanitizer report or a timeout always fails.
  if [ "$SANITIZE" = 1 ] && [ -s "$build_dir/Testing/Temporary/LastTestsFailed.log" ] &&
    ! grep -qE 'ERROR: (Address|Leak)Sanitizer|runtime error:|\*\*\*Timeout' "$ctest_log"; then
    rerun_start=$(date +%s)
    for attempt in 1 2 3; do
      echo "test: the failed tests once more, one at a time (attempt $attempt of 3):"
      if ctest --test-dir "$build_dir" --rerun-failed --output-on-failure -j 1; then
        echo "test: FLAKY under the sanitizers (failed, then passed alone on attempt $attempt):"
        grep -E '\*\*\*(Failed|Exception)' "$ctest_log" || true
        status=0
        break
      fi
    done
    echo "test: the reruns took $(( $(date +%s) - rerun_start )) s"
  fi
fi
[ "$fuzz_status" = 0 ] || { echo "test: the fuzzing campaign failed ($fuzz_status)"; exit 1; }
exit "$status"
