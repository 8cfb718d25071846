#!/usr/bin/env bash
# Builds the Blender add-on's Linux native modules, one per CPython ABI that Blender releases bundle (3.10, 3.11,
# 3.13), into OUT_DIR, and checks each; scripts/package.sh zips them.
#
# Usage: scripts/build_modules.sh OUT_DIR
#
# Baseline: Blender's own, glibc 2.28 (Rocky 8, manylinux_2_28), and no symbol of the system's C++ runtime: Blender
# links libstdc++ itself, so the module brings its own and shows none of it. The compiler is zig's clang (the
# `ziglang` package from PyPI), which targets an older glibc by name (-target x86_64-linux-gnu.2.28) and links its
# libc++, libc++abi and libunwind statically; a version script exports PyInit__loopsub alone (zig's linker has no
# --exclude-libs), so no C++ runtime symbol is exported or interposed and exceptions never cross runtimes.
# pybind11 3.x from PyPI (NumPy 2, Python 3.13). Both go into a virtual environment, build/venv-tools, made once.
# zig builds its runtime libraries once into its own cache (~/.cache/zig, or ZIG_GLOBAL_CACHE_DIR): the first run
# takes a minute or two more.
#
# One CMake tree, build/modules, serves every ABI: it is reconfigured for each interpreter (the Python entries of its
# cache dropped first), so the core is compiled once and only the binding (native/python/module.cpp) again.
#
# Each module is checked, and the script fails on the first that does not pass: objdump -T names no GLIBC_ version
# past 2.28 and no GLIBCXX_ or CXXABI_ symbol, it needs no C++ runtime library, nm -D exports PyInit__loopsub alone,
# it imports in its interpreter, and its best_kernel() is the one /proc/cpuinfo says this CPU runs (zig's
# compiler-rt only stubs __builtin_cpu_supports, which the core therefore does not use: native/src/kernels/cpu_features.cpp).
# One line a module says so. An ABI with no
# interpreter here is skipped with a message, never silently.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
source scripts/interpreters.sh
out=${1:?usage: scripts/build_modules.sh OUT_DIR}
name=$(basename "$0" .sh)

max_glibc=2.28
arch=$(uname -m)
target=$arch-linux-gnu.$max_glibc
# Versions the checks were made with: a newer zig may change its runtime.
requirements=("ziglang==0.17.1" "pybind11==3.1.0")

fail() { echo "$name: $*" >&2; exit 1; }

source scripts/packages.sh
install_packages cmake binutils python3-venv  # binutils: objdump, nm, readelf, strip

# The tools' virtual environment, (re)installed when the requirements above change.
tools=$root/build/venv-tools
ensure_venv "$tools" /usr/bin/python3 "${requirements[@]}"

# The compiler CMake is given: zig's C++ driver for the target, through a wrapper (CMake wants one executable).
toolchain=$root/build/zig-toolchain
mkdir -p "$toolchain" "$toolchain/python-multiarch"
write_if_changed() {  # FILE, the content on stdin: rewritten only when it differs (an unchanged compiler stays old)
  local content
  content=$(cat)
  [ -f "$1" ] && [ "$(cat "$1")" = "$content" ] || printf '%s\n' "$content" >"$1"
}
write_if_changed "$toolchain/c++" <<EOF
#!/bin/sh
exec "$tools/bin/python" -m ziglang c++ -target $target "\$@"
EOF
chmod +x "$toolchain/c++"
# Everything local but the module's entry point: the static libc++ and the core stay invisible to other libraries.
write_if_changed "$toolchain/module.map" <<'EOF'
{
  global: PyInit__loopsub;
  local: *;
};
EOF
link_flags="-Wl,--version-script=$toolchain/module.map"

# The kernel the core must pick here: the widest this CPU runs (its dispatch, native/src/kernels/kernels_dispatch.cpp).
cpu_flags=" $(grep -m1 '^flags' /proc/cpuinfo | cut -d: -f2 || true) "
expected_kernel=scalar
if [ "$arch" = x86_64 ]; then
  if [[ $cpu_flags == *" avx2 "* && $cpu_flags == *" fma "* ]]; then
    expected_kernel=avx2
  elif [[ $cpu_flags == *" sse4_1 "* ]]; then
    expected_kernel=sse4.1
  fi
fi


mkdir -p "$out"
tree=build/modules
pybind11_dir=$("$tools/bin/python" -m pybind11 --cmakedir)
built=0
for version in 3.10 3.11 3.13; do
  python=$(find_interpreter $version)
  if [ -z "$python" ]; then
    echo "$name: skipped CPython $version: no interpreter with its headers here (install python$version-dev or pyenv's $version)"
    continue
  fi
  suffix=$("$python" -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')
  # Debian's Python.h includes <x86_64-linux-gnu/python3.X/pyconfig.h> from /usr/include, which zig does not search
  # (its own glibc 2.28 headers stand there): that one folder is linked into build/zig-toolchain/python-multiarch.
  multiarch=$("$python" -c 'import os, sysconfig
include = sysconfig.get_paths()["include"]
relative = os.path.join(sysconfig.get_config_var("MULTIARCH") or "-", os.path.basename(include))
if os.path.isfile(os.path.join(os.path.dirname(include), relative, "pyconfig.h")):
    print(os.path.dirname(include), relative)')
  if [ -n "$multiarch" ]; then
    read -r parent relative <<<"$multiarch"
    mkdir -p "$(dirname "$toolchain/python-multiarch/$relative")"
    ln -sfn "$parent/$relative" "$toolchain/python-multiarch/$relative"
  fi
  # CMake's configuration checks only compile (STATIC_LIBRARY): linking executables would make zig build and cache its
  # runtime libraries a second time, in another variant, for them alone (a minute on a first run).
  start=$SECONDS
  cmake -S . -B "$tree" -U '*Python*' -U '*PYTHON*' -DCMAKE_BUILD_TYPE=Release \
    -DLOOPSUB_TESTS=OFF -DLOOPSUB_BENCH=OFF -DLOOPSUB_BLENDER= -DLOOPSUB_COPY_TO_ADDON=OFF \
    -DCMAKE_CXX_COMPILER="$toolchain/c++" -DCMAKE_CXX_FLAGS="-isystem $toolchain/python-multiarch" \
    -DCMAKE_MODULE_LINKER_FLAGS="$link_flags" -DCMAKE_TRY_COMPILE_TARGET_TYPE=STATIC_LIBRARY \
    -DLOOPSUB_PYTHON=ON -Dpybind11_DIR="$pybind11_dir" -DPYBIND11_FINDPYTHON=ON \
    -DPython_EXECUTABLE="$python" -DPYTHON_EXECUTABLE="$python" >/dev/null
  rm -f "$tree/native/_loopsub$suffix"  # linked anew: the link flags are no dependency of it
  cmake --build "$tree" -j"$(nproc)" --target _loopsub >/dev/null
  seconds=$((SECONDS - start))
  module=$out/_loopsub$suffix
  [ -f "$tree/native/_loopsub$suffix" ] || fail "no $tree/native/_loopsub$suffix after the build for $python"
  cp "$tree/native/_loopsub$suffix" "$module"
  # Without the debug information of zig's runtime libraries (15 MB). binutils' strip, not zig's -s: zig would build
  # and cache its runtime libraries a second time, stripped, for the module alone (a minute on a first run).
  strip --strip-all "$module"

  symbols=$(objdump -T "$module")
  glibc=$(grep -o 'GLIBC_[0-9][0-9.]*' <<<"$symbols" | sort -uV | tail -1 || true)
  [ -n "$glibc" ] || fail "$module: objdump -T shows no GLIBC_ version (not a module for glibc?)"
  [ "$(printf '%s\n' "${glibc#GLIBC_}" "$max_glibc" | sort -V | tail -1)" = "$max_glibc" ] \
    || fail "$module needs $glibc, past glibc $max_glibc: $(grep "$glibc" <<<"$symbols" | awk '{print $NF}' | xargs)"
  if grep -E 'GLIBCXX_|CXXABI_' <<<"$symbols" >&2; then
    fail "$module needs the system's C++ runtime (the GLIBCXX_/CXXABI_ symbols above)"
  fi
  runtime=$(readelf -d "$module" | grep NEEDED | grep -E 'libstdc\+\+|libc\+\+|libgcc_s|libunwind' || true)
  [ -z "$runtime" ] || fail "$module needs a C++ runtime library: $runtime"
  exports=$(nm -D --defined-only "$module" | awk '{print $NF}' | xargs)
  [ "$exports" = PyInit__loopsub ] || fail "$module exports more than PyInit__loopsub: $exports"
  # Imported alone, from a folder holding nothing else.
  alone=$(mktemp -d)
  cp "$module" "$alone"/
  kernel=$(cd "$alone" && "$python" -c 'import _loopsub; print(_loopsub.best_kernel())') \
    || { rm -rf "$alone"; fail "$module does not import in $python"; }
  rm -rf "$alone"
  [ "$kernel" = "$expected_kernel" ] \
    || fail "$module picks the '$kernel' kernel, this CPU runs '$expected_kernel' (/proc/cpuinfo)"
  echo "$name: $(basename "$module") for CPython $version ($python), configured and built in ${seconds} s: imports, best kernel $kernel," \
    "exports PyInit__loopsub alone, no GLIBCXX_/CXXABI_ symbol, needs $glibc (<= $max_glibc)"
  built=$((built + 1))
done
((built)) || fail "no native module could be built"
