#!/usr/bin/env bash
# Benchmarks the add-on against Blender's Subdivision Surface in one headless Blender run (Apply, edits, playback).
# Sets the project up first when the native module is not built.
# Usage: scripts/bench_blender.sh [--repeat N]   (background: Apply, edits, playback)
#        scripts/bench_blender.sh --gui          (Edit Mode with redraws, in Blender's interface under Xvfb)
set -euo pipefail
cd "$(dirname "$0")/.."
compgen -G "addon/_loopsub*.so" >/dev/null || scripts/setup.sh
if [ "${1:-}" = "--gui" ]; then
  command -v xvfb-run >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xvfb; }
  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --python bench/blender_gui_edit_bench.py \
    -- --addon-dir addon 2>&1 | grep -E '^gui-edit'
  exit
fi
blender --background --factory-startup --python bench/blender_modifier_bench.py -- --addon-dir addon "$@" 2>&1 |
  grep -E '^(Blender [0-9]|apply|edit|play)'
