#!/usr/bin/env bash
# Installs what the project needs on a fresh Debian 12 machine and builds everything into build/, then packs the
# Blender add-on as users install it (scripts/package.sh: build/dist/*.zip, unpacked into build/packaged-addon/, which
# the Blender tests load).
# Usage: scripts/setup.sh [--sanitize]   (--sanitize: a Debug build with ASan + UBSan into build-asan/, no package)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libgtest-dev libgmock-dev libbenchmark-dev libosd-dev
          pybind11-dev python3-dev python3-numpy python3-pytest python3-hypothesis blender assimp-testmodels clang-format
          xvfb)
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
# The linter the tests run (lint.ruff; its rules in pyproject.toml), pinned: a newer ruff may add findings.
source scripts/interpreters.sh
ensure_venv build/venv-lint /usr/bin/python3 ruff==0.17.6
cmake -S . -B "$build" "${flags[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
echo "setup: built into $build/"
[ "$build" = build ] || exit 0

scripts/package.sh --out build/dist
rm -rf build/packaged-addon
/usr/bin/python3 -c 'import sys, zipfile; zipfile.ZipFile(sys.argv[1]).extractall(sys.argv[2])' \
  build/dist/*.zip build/packaged-addon
echo "setup: the add-on as users install it: $(ls build/dist/*.zip), unpacked into build/packaged-addon/"
