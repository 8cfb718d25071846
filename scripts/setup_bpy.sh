#!/usr/bin/env bash
# Makes the virtual environments of the Blenders that the add-on's tests run in as a Python module (PyPI's bpy wheels):
# build/bpy-<series> for each line of tests/blender/bpy_versions.txt, with the CPython that series bundles (Debian's or pyenv's)
# and the NumPy it bundles. An environment that already holds its line's packages is kept (about 30 s and 400 MB of
# download each otherwise).
# Usage: scripts/setup_bpy.sh
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/interpreters.sh

while read -r series wheel python numpy; do
  [[ -z "$series" || "$series" == \#* ]] && continue
  interpreter=$(find_interpreter "$python")
  if [ -z "$interpreter" ]; then
    echo "setup_bpy: no CPython $python here (pyenv install $python, or python$python from Debian)" >&2
    exit 1
  fi
  venv=build/bpy-$series
  ensure_venv "$venv" "$interpreter" "$wheel" "$numpy"
  "$venv/bin/python" -c 'import bpy, numpy; print("setup_bpy:", bpy.app.version_string, "numpy", numpy.__version__)'
done <tests/blender/bpy_versions.txt
