#!/usr/bin/env bash
# Sets gearnvh up on a Debian machine: installs packages (idempotent), configures and builds the
# command line and the Python module (build/python: PYTHONPATH=build/python python3 -c 'import gearnvh').
#   bash scripts/setup.sh            Release build in build/
# Environment: GEARNVH_BUILD_DIR (default build), GEARNVH_CMAKE_ARGS (extra cmake arguments),
# GEARNVH_BUILD_TARGETS (default: all).
set -euo pipefail
cd "$(dirname "$0")/.."
start=$(date +%s)
bash scripts/install-deps.sh
echo "setup: install took $(( $(date +%s) - start )) s"
start=$(date +%s)
BUILD_DIR=${GEARNVH_BUILD_DIR:-build}
# shellcheck disable=SC2086
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release ${GEARNVH_CMAKE_ARGS:-}
# shellcheck disable=SC2086
cmake --build "$BUILD_DIR" -j "$(nproc)" ${GEARNVH_BUILD_TARGETS:+--target $GEARNVH_BUILD_TARGETS}
echo "setup: configure and build of $BUILD_DIR took $(( $(date +%s) - start )) s"
