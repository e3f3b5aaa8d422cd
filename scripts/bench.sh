#!/usr/bin/env bash
# Builds the benchmarks (on demand, Release, -march=native) and runs one harness:
#   bash scripts/bench.sh [--quick] [--json FILE]            the real-time frontier (every tier,
#        constant contact, event paths, flexible tiers, CVODE peer, atlas throughput, reduction)
#   bash scripts/bench.sh --paper [--quick] [--json FILE]    the preprint's strong-rattle point,
#        like for like, with the matvec floor measured in the same run
# See docs/BENCHMARKS.md.
set -euo pipefail
cd "$(dirname "$0")/.."
target=bench_frontier
if [ "${1:-}" = "--paper" ]; then
  target=bench_paper_point
  shift
fi
bash scripts/install-deps.sh
cmake -S . -B build-bench -G Ninja -DCMAKE_BUILD_TYPE=Release -DGEARNVH_BUILD_BENCH=ON \
  -DGEARNVH_BUILD_TESTS=OFF > /dev/null
cmake --build build-bench --target "$target" -j "$(nproc)"
"./build-bench/bench/$target" "$@"
