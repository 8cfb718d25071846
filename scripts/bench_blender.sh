#!/usr/bin/env bash
# Benchmarks the add-on against Blender's Subdivision Surface in one headless Blender run (Apply, edits, playback).
# Sets the project up first when the native module is not built. Usage: scripts/bench_blender.sh [--repeat N]
set -euo pipefail
cd "$(dirname "$0")/.."
compgen -G "addon/_loopsub*.so" >/dev/null || scripts/setup.sh
blender --background --factory-startup --python bench/blender_modifier_bench.py -- --addon-dir addon "$@" 2>&1 |
  grep -E '^(Blender [0-9]|apply|edit|play)'
