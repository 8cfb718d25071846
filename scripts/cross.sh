#!/usr/bin/env bash
# Builds the core and the CLI for another platform with Debian's cross toolchains and checks them against this
# machine's build: every OpenSubdiv peer shape at levels 1-3 under both rule sets gives the same faces and the same
# positions within 1e-6 of the bounding-box diagonal, and the CLI tests pass with the cross-built binary.
#   windows: x86_64-w64-mingw32-g++ (posix threads), run under wine64 (SSE4.1/AVX2 kernels as here)
#   arm64:   aarch64-linux-gnu-g++, run under qemu-user (the scalar kernel: the SIMD kernels are x86-64 only)
# Usage: scripts/cross.sh windows|arm64 [--if-installed]
#   --if-installed: when the toolchain or emulator is missing, say so and exit 77 (ctest's "skipped") instead of
#                   installing it with apt-get.
set -euo pipefail
cd "$(dirname "$0")/.."
target="${1:?usage: scripts/cross.sh windows|arm64 [--if-installed]}"
if_installed=0; [ "${2:-}" = --if-installed ] && if_installed=1

case "$target" in
  windows) packages=(g++-mingw-w64-x86-64 wine64)
           compiler=x86_64-w64-mingw32-g++-posix system=Windows processor=x86_64 exe=loopsub.exe ;;
  arm64)   packages=(g++-aarch64-linux-gnu qemu-user)
           compiler=aarch64-linux-gnu-g++ system=Linux processor=aarch64 exe=loopsub ;;
  *) echo "cross: unknown target '$target' (windows or arm64)" >&2; exit 2 ;;
esac
source scripts/packages.sh
mapfile -t missing < <(missing_packages "${packages[@]}")
if ((${#missing[@]} && if_installed)); then
  echo "cross: $target skipped: ${missing[*]} not installed (scripts/cross.sh $target installs them)"
  exit 77
fi
install_packages "${packages[@]}"
shapes=../shared/peer/opensubdiv-loop-shapes
if [ ! -d "$shapes" ]; then
  echo "cross: skipped: OpenSubdiv's Loop shapes are not in $shapes (clone beside the team's shared folder)"
  exit 77
fi

build=build-$target
cmake -S . -B "$build" -DCMAKE_SYSTEM_NAME=$system -DCMAKE_SYSTEM_PROCESSOR=$processor \
  -DCMAKE_CXX_COMPILER=$compiler -DCMAKE_BUILD_TYPE=Release -DCMAKE_EXE_LINKER_FLAGS=-static \
  -DLOOPSUB_TESTS=OFF -DLOOPSUB_BENCH=OFF -DLOOPSUB_PYTHON=OFF -DLOOPSUB_BLENDER= >/dev/null
cmake --build "$build" -j"$(nproc)" --target loopsub >/dev/null
[ -x build/loopsub ] || scripts/setup.sh >/dev/null

# A command that runs the cross-built CLI here, for the comparison and for the CLI tests.
runner="$PWD/$build/run-loopsub"
case "$target" in
  windows)
    # A Wine prefix of its own, and one wineserver kept up for the whole run: a server that quits between two of the
    # hundreds of short runs here resets the next client's connection ("wine client error ... recvmsg").
    export WINEPREFIX="$PWD/$build/wineprefix" WINEDEBUG=-all
    mkdir -p "$WINEPREFIX"
    /usr/lib/wine/wineserver -p
    printf '#!/bin/sh\nexec /usr/lib/wine/wine64 %s "$@"\n' "$PWD/$build/$exe" >"$runner" ;;
  arm64)   printf '#!/bin/sh\nexec qemu-aarch64 %s "$@"\n' "$PWD/$build/$exe" >"$runner" ;;
esac
chmod +x "$runner"

work=$(mktemp -d)
trap 'rm -rf "$work"; [ "$target" != windows ] || /usr/lib/wine/wineserver -k 2>/dev/null || true' EXIT
compared=0
for shape in "$shapes"/*.obj; do
  for rules in hoppe94 opensubdiv; do
    for levels in 1 2 3; do
      native="$work/native.obj" cross="$work/cross.obj"
      if build/loopsub "$shape" "$native" --levels $levels --rules $rules 2>/dev/null; then
        "$runner" "$shape" "$cross" --levels $levels --rules $rules 2>/dev/null \
          || { echo "cross: $target: $(basename "$shape") $rules L$levels failed where the native build worked" >&2; exit 1; }
        /usr/bin/python3 scripts/compare_obj.py "$native" "$cross" 1e-6 \
          || { echo "cross: $target: $(basename "$shape") $rules L$levels differs" >&2; exit 1; }
        compared=$((compared + 1))
      else
        # The native build refuses it (a shape with degenerate faces): the cross build must refuse it too.
        ! "$runner" "$shape" "$cross" --levels $levels --rules $rules 2>/dev/null \
          || { echo "cross: $target: $(basename "$shape") accepted where the native build refused it" >&2; exit 1; }
      fi
    done
  done
done
echo "cross: $target: $compared refinements equal to the native build's"

status=0
for test in tests/cli/test_*.sh; do
  if ! bash "$test" "$runner" "$shapes" >"$work/cli.log" 2>&1; then
    echo "cross: $target: $(basename "$test") failed:" >&2
    tail -20 "$work/cli.log" >&2
    status=1
  fi
done
((status)) || echo "cross: $target: the CLI tests pass"
exit $status
