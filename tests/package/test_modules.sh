#!/usr/bin/env bash
# Runs the Python tests (tests/python/) against each native module that scripts/package.sh staged, in the
# interpreter the module is for, with the NumPy that Blender bundles with that interpreter: NumPy 1.26 with CPython
# 3.10 and 3.11, NumPy 2.3 with CPython 3.13. Each runs in a virtual environment of its own under build/
# (venv-cp310-numpy1, venv-cp311-numpy1, venv-cp313-numpy2: that NumPy, pytest and hypothesis from PyPI, made once),
# with only that module on PYTHONPATH and LOOPSUB_CLI set to the CLI (build/loopsub), as ctest sets them.
#
# Usage: tests/package/test_modules.sh STAGE_DIR   (scripts/package.sh stages into build-package/)
# Ends with 'N passed, N failed' (modules); exits non-zero when a module fails or none is found.
set -euo pipefail
stage=${1:?usage: tests/package/test_modules.sh STAGE_DIR}
stage=$(cd "$stage" && pwd)
cd "$(dirname "$0")/../.."
root=$PWD
source scripts/interpreters.sh
name=test_modules

cli=$root/build/loopsub
[ -x "$cli" ] || { echo "$name: no CLI at build/loopsub (scripts/setup.sh builds it); some tests need it" >&2; exit 1; }


numpy_for() {  # the NumPy that Blender bundles with CPython $1: "major requirement"
  case "$1" in
    3.10 | 3.11) echo "1 numpy==1.26.*" ;;
    *) echo "2 numpy==2.3.*" ;;
  esac
}

shopt -s nullglob
modules=("$stage"/_loopsub*.so)
((${#modules[@]})) || { echo "$name: no native module (_loopsub*.so) in $stage" >&2; exit 1; }

passed=0 failed=0
for module in "${modules[@]}"; do
  file=$(basename "$module")
  tag=$(sed -n 's/^_loopsub\.cpython-\([0-9]\)\([0-9]*\)-.*/\1.\2/p' <<<"$file")
  if [ -z "$tag" ]; then
    echo "$name: FAILED $file: not a CPython module name (_loopsub.cpython-3XY-...)"; failed=$((failed + 1)); continue
  fi
  python=$(find_interpreter "$tag")
  if [ -z "$python" ]; then
    echo "$name: FAILED $file: no CPython $tag here"; failed=$((failed + 1)); continue
  fi
  read -r major numpy <<<"$(numpy_for "$tag")"
  requirements=("$numpy" pytest hypothesis)
  venv=$root/build/venv-cp${tag/./}-numpy$major
  ensure_venv "$venv" "$python" "${requirements[@]}"


  # The module alone on the path, run from a folder of its own (not the checkout, whose addon/ may hold another).
  work=$(mktemp -d)
  mkdir "$work/module"
  cp "$module" "$work/module/"
  versions=$("$venv/bin/python" -c 'import sys, numpy; print(f"CPython {sys.version.split()[0]}, NumPy {numpy.__version__}")') \
    || versions="no NumPy that imports"
  echo "$name: $file with $versions ($python, build/$(basename "$venv"))"
  # The interpreter finds this very module, not another one elsewhere on its path.
  loaded=$(cd "$work" && PYTHONPATH="$work/module" "$venv/bin/python" -c 'import _loopsub; print(_loopsub.__file__)') \
    || loaded="nothing (the import fails)"
  if [ "$loaded" != "$work/module/$file" ]; then
    echo "$name: FAILED $file: $venv/bin/python imports $loaded"; failed=$((failed + 1))
  elif (cd "$work" && PYTHONPATH="$work/module" LOOPSUB_CLI="$cli" \
          "$venv/bin/python" -m pytest -q -p no:cacheprovider "$root/tests/python"); then
    passed=$((passed + 1))
  else
    echo "$name: FAILED $file with $versions"; failed=$((failed + 1))
  fi
  rm -rf "$work"
done

echo "$passed passed, $failed failed"
((failed == 0))
