#!/usr/bin/env bash
# Retakes the docs' screenshots of the add-on's panel in Debian's Blender 3.4.1, its real interface under Xvfb:
# add-modifier-menu.png, modifier-panel.png and modifier-adaptive.png with the add-on as users
# install it (build/packaged-addon/), then modifier-without-addon.png from a second Blender without the add-on,
# opening the file the first one saved. What each shows: scripts/screenshots.py.
# Usage: scripts/screenshots.sh [--out docs]
set -euo pipefail
cd "$(dirname "$0")/.."

out=docs
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out=${2:?--out needs a folder}; shift 2 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"

addon=build/packaged-addon/loop_subdivision
[ -d "$addon" ] || scripts/setup.sh
missing=()
command -v xvfb-run >/dev/null || missing+=(xvfb)
command -v convert >/dev/null || missing+=(imagemagick)
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Each run quits Blender itself; the timeout (inside xvfb-run, so that xvfb-run still takes its X server down) guards
# against an interface that stops drawing. -a: a free display, another Xvfb may be running. -p: the window fills the
# screen (no window manager places it). Software OpenGL: Xvfb has no GPU.
run() {
  local size=$1; shift
  LIBGL_ALWAYS_SOFTWARE=1 xvfb-run -a -s "-screen 0 1600x1000x24" \
    timeout --kill-after=10 120 blender --factory-startup -p 0 0 $size "$@" >>"$work/blender.log" 2>&1 || {
      tail -n 40 "$work/blender.log" >&2
      echo "screenshots: Blender failed" >&2
      exit 1
    }
}
run "1600 1000" --python scripts/screenshots.py -- --addon-dir "$addon" --out "$out" --save "$work/entry.blend"
# A Blender without the add-on: the packaged folder is never installed, so --factory-startup leaves it out. A
# smaller window: its picture holds the viewport too, at full height.
run "1120 720" "$work/entry.blend" --python scripts/screenshots.py -- --out "$out"
grep '^screenshots:' "$work/blender.log"
