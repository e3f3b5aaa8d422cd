#!/usr/bin/env bash
# Installs every Debian package gearnvh needs. Idempotent and non-interactive.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev liblapack-dev libspectra-dev libfftw3-dev libyaml-cpp-dev
  libvtk9-dev libopenmpi-dev openmpi-bin
  catch2 libcli11-dev libfmt-dev nlohmann-json3-dev libsundials-dev libbenchmark-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  xvfb xauth libgl1-mesa-dri chromium
  clang libclang-rt-14-dev
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#PKGS[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
