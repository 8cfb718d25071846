#!/usr/bin/env bash
# Installs what the project needs on a fresh Debian 12 machine and builds everything into build/.
# Usage: scripts/setup.sh [--sanitize]   (--sanitize: a Debug build with ASan + UBSan into build-asan/)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libgtest-dev libgmock-dev libbenchmark-dev libosd-dev
          pybind11-dev python3-dev python3-numpy python3-pytest python3-hypothesis blender assimp-testmodels)
source scripts/packages.sh
install_packages "${packages[@]}"

build=build
flags=(-DCMAKE_BUILD_TYPE=Release)
if [ "${1:-}" = "--sanitize" ]; then
  build=build-asan
  # The sanitizer run covers the native tests, the CLI and the Python module (its tests with the runtime preloaded;
  # the module stays out of addon/, and Blender out of the run).
  flags=(-DCMAKE_BUILD_TYPE=Debug -DLOOPSUB_SANITIZE=ON -DLOOPSUB_COPY_TO_ADDON=OFF -DLOOPSUB_BLENDER= -DLOOPSUB_BENCH=OFF)
fi
cmake -S . -B "$build" "${flags[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
echo "setup: built into $build/"
