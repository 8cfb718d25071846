#!/usr/bin/env bash
# Installs what the project needs on a fresh Debian 12 machine and builds everything into build/.
# Usage: scripts/setup.sh [--sanitize]   (--sanitize: a Debug build with ASan + UBSan into build-asan/)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libgtest-dev libgmock-dev libbenchmark-dev libosd-dev
          pybind11-dev python3-dev python3-numpy python3-pytest blender assimp-testmodels)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=(); [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

build=build
flags=(-DCMAKE_BUILD_TYPE=Release)
if [ "${1:-}" = "--sanitize" ]; then
  build=build-asan
  # The Python module and Blender load the sanitised core only with the runtime preloaded: the sanitizer run
  # covers the native tests and the CLI.
  flags=(-DCMAKE_BUILD_TYPE=Debug -DLOOPSUB_SANITIZE=ON -DLOOPSUB_PYTHON=OFF -DLOOPSUB_BLENDER= -DLOOPSUB_BENCH=OFF)
fi
cmake -S . -B "$build" "${flags[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
echo "setup: built into $build/"
