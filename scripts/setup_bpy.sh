#!/usr/bin/env bash
# Makes the virtual environments of the Blenders that the add-on's tests run in as a Python module (PyPI's bpy wheels):
# build/bpy-<series> for each line of tests/blender/bpy_versions.txt, with the CPython that series bundles (pyenv's)
# and the NumPy it bundles. An environment that already holds its line's packages is kept (about 30 s and 400 MB of
# download each otherwise).
# Usage: scripts/setup_bpy.sh
set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/interpreters.sh

while read -r series wheel python numpy; do
  [[ -z "$series" || "$series" == \#* ]] && continue
  venv=build/bpy-$series
  stamp="$venv/.loopsub-installed"
  wanted="$wheel $numpy"
  if [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$wanted" ]; then
    continue
  fi
  interpreter=$(find_interpreter "$python")
  if [ -z "$interpreter" ]; then
    echo "setup_bpy: no CPython $python here (pyenv install $python, or python$python from Debian)" >&2
    exit 1
  fi
  echo "setup_bpy: $venv: $wheel with $numpy on $("$interpreter" -V)"
  rm -rf "$venv"
  "$interpreter" -m venv "$venv"
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "$wheel" "$numpy" 2>&1 | grep -v '^WARNING: Location' || true
  "$venv/bin/python" -c 'import bpy, numpy; print("setup_bpy:", bpy.app.version_string, "numpy", numpy.__version__)'
  echo "$wanted" >"$stamp"
done <tests/blender/bpy_versions.txt
