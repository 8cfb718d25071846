#!/usr/bin/env bash
# Sets up (installs and builds) if needed, then runs every test: native (GoogleTest), Python (pytest) and the
# Blender add-on in background mode, all through ctest. Ends with ctest's summary.
# Usage: scripts/test.sh [--sanitize]   (--sanitize: native tests and CLI under ASan + UBSan, in build-asan/)
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh "$@"
build=build; [ "${1:-}" = "--sanitize" ] && build=build-asan
cd "$build"
ctest --output-on-failure -j2 --timeout 600
