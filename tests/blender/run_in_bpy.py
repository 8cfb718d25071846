"""Runs one Blender test script in Blender as a Python module (PyPI's bpy wheels), as `blender --background
--python-exit-code 1 --python SCRIPT -- ARGS` runs it in the full program.

Usage: PYTHON run_in_bpy.py SCRIPT -- ARGS   (PYTHON: the interpreter of a virtual environment with bpy installed)

bpy is imported first (bmesh, mathutils and the rest exist only once it is), the script runs as __main__ with
sys.argv as Blender would give it, and the process ends through os._exit: the bpy wheels can hang in their exit
handlers after a failed script (seen in 4.5: a file-closing thread waited on forever), which would cost ctest its
whole timeout instead of a failure.
"""
import os
import runpy
import sys
import traceback

import bpy  # noqa: F401  (must come before the script's imports)


def main():
    script = os.path.abspath(sys.argv[1])
    sys.argv = [bpy.app.binary_path or sys.executable, "--python", script] + sys.argv[2:]
    sys.path.insert(0, os.path.dirname(script))
    code = 0
    try:
        runpy.run_path(script, run_name="__main__")
    except SystemExit as exit_:
        code = exit_.code if isinstance(exit_.code, int) else (0 if exit_.code is None else 1)
    except BaseException:  # noqa: B036  (a failed script, whatever it raised, is a failed test)
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


main()
