#!/usr/bin/env bash
# Runs the whole gearnvh test suite (Catch2 and the Python module's pytest, through ctest).
#   bash scripts/test.sh             Release build in build/
#   bash scripts/test.sh --sanitize  the instrumented build in build-asan/ (clang, AddressSanitizer +
#                                    UndefinedBehaviorSanitizer); the Release-only tests are not
#                                    built there (docs/testing.md says which and why)
# Each phase prints its seconds (install, build, tests).
set -euo pipefail
cd "$(dirname "$0")/.."
if [ "${1:-}" = "--sanitize" ]; then
  # shellcheck source=scripts/instrumented.sh
  source scripts/instrumented.sh
fi
bash scripts/setup.sh
start=$(date +%s)
ctest --test-dir "${GEARNVH_BUILD_DIR:-build}" --output-on-failure -j "$(nproc)"
echo "test: tests in ${GEARNVH_BUILD_DIR:-build} took $(( $(date +%s) - start )) s"
