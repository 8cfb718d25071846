# Sourced by the scripts that need a given CPython or a virtual environment of one (the add-on's modules, their
# tests, the bpy environments, the build tools).
#   find_interpreter X.Y              prints a CPython X.Y with its headers: Debian's /usr/bin/pythonX.Y, else pyenv's
#   ensure_venv DIR PYTHON REQ...     makes the virtual environment DIR of PYTHON with the requirements pip-installed,
#                                     unless DIR already holds exactly these (its requirements.txt); says when it does
find_interpreter() {
  local candidate
  for candidate in "/usr/bin/python$1" "$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")"/versions/"$1".*/bin/python"$1"; do
    [ -x "$candidate" ] || continue
    "$candidate" -c 'import os, sysconfig, sys; sys.exit(not os.path.isfile(os.path.join(sysconfig.get_paths()["include"], "Python.h")))' \
      2>/dev/null && { echo "$candidate"; return; }
  done
}

ensure_venv() {
  local venv=$1 python=$2
  shift 2
  local wanted="$python $*"
  [ -x "$venv/bin/python" ] && [ "$(cat "$venv/requirements.txt" 2>/dev/null)" = "$wanted" ] && return 0
  echo "$(basename "$0" .sh): installing $* into $venv ($("$python" -V))"
  rm -rf "$venv"
  "$python" -m venv "$venv" || { echo "$(basename "$0" .sh): $python cannot make a virtual environment" >&2; return 1; }
  "$venv/bin/python" -m pip install --quiet --disable-pip-version-check "$@" || return 1
  echo "$wanted" >"$venv/requirements.txt"
}
