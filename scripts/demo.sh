#!/usr/bin/env bash
# The demo in one command: Loop-subdivides a UV-mapped, creased cage with the Blender add-on in headless Blender (limit
# surface and limit normals), saves the scene as a .blend and renders the cage, the add-on's result and Blender's own
# Subdivision Surface with the same settings side by side, under a UV checker (Cycles, CPU).
# Sets the project up first (scripts/setup.sh) when it was never built.
#
# Usage: scripts/demo.sh [PATH.obj|PATH.blend] [--levels N] [--rules HOPPE94|OPENSUBDIV] [--out DIR]
#   no path: a built-in tufted cushion with creases, tagged corners and a UV map; a path: that OBJ (OpenSubdiv's
#   `t crease` and `t corner` tags are read too) or the active (else first) mesh object of that .blend (without a UV
#   map, the demo unwraps it with Smart UV Project).
#   Writes DIR/demo.blend and DIR/demo.png; DIR defaults to out/ in the repository.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"

if ! command -v blender >/dev/null || ! compgen -G "$repo/build/native/_loopsub*.so" >/dev/null \
   || ! compgen -G "$repo/addon/_loopsub*.so" >/dev/null; then
  echo "demo: Blender, the build or the native module in addon/ is missing: running scripts/setup.sh"
  "$repo/scripts/setup.sh"
fi

# Paths stay relative to the caller's directory: Blender runs from here. Cycles' per-sample progress lines are
# dropped (sed always succeeds, so pipefail reports Blender's own exit status).
blender --background --factory-startup --python-exit-code 1 --python "$repo/scripts/demo_blender.py" -- "$@" \
  | sed -u '/^Fra:/d'
