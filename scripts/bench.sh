#!/usr/bin/env bash
# Builds the benchmarks (on demand, Release, -march=native) and runs the frontier harness:
#   bash scripts/bench.sh [--quick] [--json FILE]
# Prints one table per section (step cost per tier, constant contact, event paths, flexible tiers,
# CVODE peer, atlas throughput, reduction); --json writes every figure. See docs/BENCHMARKS.md.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DGEARNVH_BUILD_BENCH=ON \
  -DGEARNVH_BUILD_TESTS=OFF > /dev/null
cmake --build build-bench --target bench_frontier -j "$(nproc)"
./build-bench/bench/bench_frontier "$@"
