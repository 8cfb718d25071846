#!/usr/bin/env bash
# Interactive latency in Blender's real interface (under Xvfb, Mesa's software OpenGL): edit -> first draw (with
# Loop Subdivision's limit normals, written on every update) and the longest stall of the main thread during a 30 Hz
# drag with a hold, Loop Subdivision against Subdivision Surface (GPU subdivision on, as
# Blender's default, and off) on a 100,352-triangle cage. The add-on is loaded as users install it
# (build/packaged-addon/). Prints a markdown table; what each number means is in scripts/bench_gui.py.
# Usage: scripts/bench_gui.sh [--blender /usr/bin/blender] [--repeat N] [--levels 1,2] [--configs "loop subsurf-gpu"]
# Takes about 15-20 minutes per round on two cores (software OpenGL, and the viewport's anti-aliasing redraws after
# each edit). Samples, log and screenshots stay in /tmp/gui_bench/ (the first screenshot also as /tmp/gui_bench.png).
set -euo pipefail
cd "$(dirname "$0")/.."

blender=/usr/bin/blender
repeat=5
levels="1 2"
configs="loop subsurf-gpu subsurf-cpu"
while [ $# -gt 0 ]; do
  case "$1" in
    --blender) blender=${2:?--blender needs a path}; shift 2 ;;
    --repeat) repeat=${2:?--repeat needs a number}; shift 2 ;;
    --levels) levels=${2:?--levels needs a list such as 1,2}; levels=${levels//,/ }; shift 2 ;;
    --configs) configs=${2:?--configs needs a list such as "loop subsurf-gpu subsurf-cpu"}; shift 2 ;;
    *) echo "unknown argument: $1" >&2; exit 2 ;;
  esac
done

addon=build/packaged-addon/loop_subdivision
[ -d "$addon" ] || scripts/setup.sh
missing=()
command -v Xvfb >/dev/null || missing+=(xvfb)
command -v import >/dev/null || missing+=(imagemagick)
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}"
fi

out=/tmp/gui_bench
rm -rf "$out" && mkdir -p "$out/addon"
# Every process loads this copy: the package may be rebuilt while a long run goes on.
echo "add-on: $addon as packed on $(date -r "$addon/__init__.py" '+%F %T'), checkout at" \
  "$(git log -1 --format=%h 2>/dev/null || echo '?')" >"$out/version"
cp -r "$addon" "$out/addon/" && addon="$out/addon/$(basename "$addon")"
# One X server for the whole run, on a display it picks itself (-displayfd), stopped by its own PID on exit.
Xvfb -displayfd 5 -screen 0 1600x1000x24 -nolisten tcp 5>"$out/display" 2>"$out/xvfb.log" &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null || true' EXIT
for _ in $(seq 100); do [ -s "$out/display" ] && break; sleep 0.1; done
export DISPLAY=":$(head -n 1 "$out/display")"

# Rounds: every configuration once per round, each in a fresh Blender, so that a shared machine's changing load
# falls on all of them alike and no configuration inherits another's memory or caches.
failed=0
for round in $(seq "$repeat"); do
  for config in $configs; do
    for level in $levels; do
      name="$config-$level"
      shot=""
      [ "$round" = 1 ] && shot="$out/$name.png"
      echo "round $round: $name" >&2
      # The script quits Blender itself; the timeout guards against an interface that stops drawing.
      if ! timeout --kill-after=10 1800 "$blender" --factory-startup -p 0 0 1600 1000 \
          --python scripts/bench_gui.py -- --addon-dir "$addon" --config "$config:$level" \
          --json "$out/$name-$round.json" --screenshot "$shot" >"$out/$name-$round.log" 2>&1 \
          || [ ! -s "$out/$name-$round.json" ]; then
        echo "bench_gui: $name failed in round $round, see $out/$name-$round.log" >&2
        rm -f "$out/$name-$round.json"
        failed=1
      fi
    done
  done
done

first=$(ls "$out"/*.png 2>/dev/null | head -n 1 || true)
[ -n "$first" ] && cp "$first" /tmp/gui_bench.png
python3 scripts/bench_gui_table.py "$out"/*.json
echo && cat "$out/version" 2>/dev/null || true
exit "$failed"
