#!/usr/bin/env bash
# Benchmarks the add-on against Blender's Subdivision Surface in one headless Blender run (Apply, edits, playback),
# on the add-on as users install it (build/packaged-addon/, packed by scripts/setup.sh).
# Usage: scripts/bench_blender.sh [--blender SERIES] [--repeat N] [--only NAME]
#          SERIES: 3.4 (Debian's Blender, the default), a bpy series of tests/blender/bpy_versions.txt (4.2, 4.5,
#          5.0, 5.2, 5.3: Blender as a Python module, build/bpy-SERIES, made by scripts/setup_bpy.sh), or all
#        scripts/bench_blender.sh --gui   (Edit Mode with redraws, in Blender 3.4.1's interface under Xvfb)
#        scripts/bench_blender.sh --adaptive-scene [FRAMES]   (Adaptive Subdivision against levels on a rendered
#          scene, in Blender 3.4.1; the pictures side by side in docs/adaptive-scene.png)
set -euo pipefail
cd "$(dirname "$0")/.."
addon=build/packaged-addon/loop_subdivision
[ -d "$addon" ] || scripts/setup.sh
if [ "${1:-}" = "--gui" ]; then
  command -v xvfb-run >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq xvfb; }
  xvfb-run -a -s "-screen 0 1600x1000x24" blender --factory-startup --python bench/blender_gui_edit_bench.py \
    -- --addon-dir "$addon" 2>&1 | grep -E '^gui-edit'
  exit
fi
if [ "${1:-}" = "--adaptive-scene" ]; then
  frames=${2:-3}
  command -v montage >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq imagemagick; }
  pictures=$(mktemp -d)
  blender --background --factory-startup --python bench/blender_adaptive_scene.py -- --addon-dir "$addon" \
    --out "$pictures" --frames "$frames" 2>&1 | grep -E '^(Blender [0-9.]+,|scene)'
  shown=(levels-2 levels-4 adaptive-length-1px adaptive-deviation-0.1px)
  tiles=()
  for frame in 1 "$frames"; do
    for way in "${shown[@]}"; do tiles+=(-label "$way, frame $frame" "$pictures/$way-frame$frame.png"); done
  done
  montage "${tiles[@]}" -tile "${#shown[@]}x2" -geometry 320x180+4+4 -pointsize 14 docs/adaptive-scene.png
  rm -rf "$pictures"
  exit
fi
series=3.4
if [ "${1:-}" = "--blender" ]; then series=${2:?--blender needs a series}; shift 2; fi
if [ "$series" = all ]; then
  series="3.4 $(grep -o '^[0-9][0-9.]*' tests/blender/bpy_versions.txt | tr '\n' ' ')"
fi
for one in $series; do
  if [ "$one" = 3.4 ]; then
    blender=(blender --background --factory-startup --python)
  else
    [ -x "build/bpy-$one/bin/python" ] || scripts/setup_bpy.sh
    blender=("build/bpy-$one/bin/python" tests/blender/run_in_bpy.py)
  fi
  "${blender[@]}" bench/blender_modifier_bench.py -- --addon-dir "$addon" "$@" 2>&1 |
    grep -E '^(Blender [0-9.]+.*medians|apply|edit|play)'
done
