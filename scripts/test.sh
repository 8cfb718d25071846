#!/usr/bin/env bash
# Sets up (installs and builds) if needed, then runs every test through one ctest run, which ends with ctest's summary:
# native (GoogleTest, against OpenSubdiv), CLI, Python (pytest), the packaged Blender add-on in background mode in
# Debian's Blender 3.4.1 and in the bpy wheels of tests/blender/bpy_versions.txt (4.2, 4.5, 5.0, 5.2, 5.3; virtual
# environments under build/, made by scripts/setup_bpy.sh), and the deep
# checks: the native, CLI and Python tests again under AddressSanitizer + UndefinedBehaviorSanitizer (build-asan/), 60 s
# of each libFuzzer target (build-fuzz/), and the Windows and ARM64 cross builds checked under wine64 and qemu-user
# where their toolchains are installed (skipped with a notice otherwise; scripts/cross.sh installs them). A few
# minutes from a fresh clone on two cores.
# Usage: scripts/test.sh [--quick | --sanitize]
#   --quick     without the deep checks and without the bpy wheels (Blender 3.4.1 only)
#   --sanitize  only the sanitizer run (native, CLI and Python tests, in build-asan/)
# Longer fuzzing: scripts/fuzz.sh --seconds 3600.
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-}"
case "$mode" in
  ""|--quick|--sanitize) ;;
  *) echo "test: unknown argument '$mode' (usage: scripts/test.sh [--quick | --sanitize])" >&2; exit 2 ;;
esac

if [ "$mode" = --sanitize ]; then
  scripts/setup.sh --sanitize
  cd build-asan
  exec ctest --output-on-failure -j2 --timeout 600
fi

scripts/setup.sh
deep=OFF bpy=OFF
if [ "$mode" != --quick ]; then
  scripts/setup_bpy.sh
  scripts/setup.sh --sanitize
  scripts/fuzz.sh --build-only
  deep=ON bpy=ON
fi
cmake -S . -B build -DLOOPSUB_DEEP_CHECKS=$deep -DLOOPSUB_BPY=$bpy >/dev/null
cd build
ctest --output-on-failure -j2 --timeout 900
