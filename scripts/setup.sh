#!/usr/bin/env bash
# Installs what pomlab needs from Debian's packages (only what is missing),
# then configures and builds it in ./build (or $POM_BUILD_DIR).
# Usage: bash scripts/setup.sh [extra cmake arguments]
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config git clang-format
  clang libclang-rt-14-dev
  libgsl-dev libconfig-dev libsundials-dev libsuitesparse-dev libnlopt-dev
  libhdf5-dev hdf5-tools libopenmpi-dev openmpi-bin
  python3 python3-numpy python3-scipy python3-h5py python3-matplotlib python3-pandas python3-pytest
  chromium libjs-three ffmpeg
  libmujoco-dev   # optional: tests/test_mjcf.c loads `pomlab export --mjcf` (skipped without)
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo_cmd apt-get update -q
  $sudo_cmd apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

build="${POM_BUILD_DIR:-build}"
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build "$build" -j"$(nproc)"
echo "setup: built $build/cli/pomlab"
