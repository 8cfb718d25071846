# Sourced by the scripts that need a given CPython (the add-on's modules, their tests, the bpy environments).
#   find_interpreter X.Y   prints a CPython X.Y with its headers: Debian's /usr/bin/pythonX.Y, else pyenv's
find_interpreter() {
  local candidate
  for candidate in "/usr/bin/python$1" "$(pyenv root 2>/dev/null || echo "$HOME/.pyenv")"/versions/"$1".*/bin/python"$1"; do
    [ -x "$candidate" ] || continue
    "$candidate" -c 'import os, sysconfig, sys; sys.exit(not os.path.isfile(os.path.join(sysconfig.get_paths()["include"], "Python.h")))' \
      2>/dev/null && { echo "$candidate"; return; }
  done
}
