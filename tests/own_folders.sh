#!/usr/bin/env bash
# Runs one test's command with a temporary folder and Blender user folders of its own, all under DIR in the build tree
# and emptied first, so that the test, and every Blender and other process it starts (they inherit the environment),
# leaves the machine as it found it: nothing outside the build tree changes (the team rule, README "Tests").
#   DIR/tmp        TMPDIR, TMP and TEMP: Python's tempfile (pytest's tmp_path too), mktemp, GoogleTest's TempDir, pip,
#                  and Blender's temporary folder (Linux: TMP, else TMPDIR, else /tmp; a folder that does not exist is
#                  passed over for /tmp): bpy.app.tempdir, the copy buffer copybuffer.blend (Ctrl C), autosaves,
#                  quit.blend, crash logs. --factory-startup keeps none of these out of /tmp.
#   DIR/config, DIR/scripts, DIR/datafiles, DIR/extensions
#                  BLENDER_USER_CONFIG, BLENDER_USER_SCRIPTS, BLENDER_USER_DATAFILES, BLENDER_USER_EXTENSIONS (4.2+),
#                  and DIR itself BLENDER_USER_RESOURCES (the root of the rest), for the program and the bpy wheels
#                  (read when bpy is imported): preferences, installed add-ons and extensions stay here, not in
#                  ~/.config/blender/.
#   DIR/cache      XDG_CACHE_HOME: the thumbnails Blender writes for each file it saves (thumbnails/), Mesa's shader
#                  cache (the interface tests under Xvfb), pip's cache.
#   DIR/pulse      PULSE_RUNTIME_PATH: Blender opens its audio device even in background mode, and PulseAudio's client,
#                  where no XDG_RUNTIME_DIR is set, makes a folder in TMPDIR and links it from ~/.config/pulse/; with
#                  it set, it does neither (and a test never talks to the desktop's sound server).
# A folder per test: tests that ctest runs side by side (-j2) share no copy buffer or file. What a test left stays in
# DIR until its next run.
# Usage: tests/own_folders.sh DIR COMMAND [ARGS...]   (tests/CMakeLists.txt runs each test through it)
set -euo pipefail
dir=${1:?usage: tests/own_folders.sh DIR COMMAND [ARGS...]}
shift
(($#)) || { echo "usage: tests/own_folders.sh DIR COMMAND [ARGS...]" >&2; exit 2; }
case "$dir" in
  /*/test-home/?*) ;;  # emptied below: only ever a test's own folder under a build tree's test-home/
  *) echo "own_folders: DIR must be an absolute path .../test-home/NAME, not '$dir'" >&2; exit 2 ;;
esac
rm -rf "$dir"
mkdir -p "$dir"/{tmp,config,scripts,datafiles,extensions,cache,pulse}
export TMPDIR=$dir/tmp TMP=$dir/tmp TEMP=$dir/tmp XDG_CACHE_HOME=$dir/cache PULSE_RUNTIME_PATH=$dir/pulse \
  BLENDER_USER_RESOURCES=$dir BLENDER_USER_CONFIG=$dir/config BLENDER_USER_SCRIPTS=$dir/scripts \
  BLENDER_USER_DATAFILES=$dir/datafiles BLENDER_USER_EXTENSIONS=$dir/extensions
exec "$@"
