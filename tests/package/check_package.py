"""Run by test_install.sh with the installed package: loopsub imports by name, its subdivide takes float64 positions
and int64 faces (as numpy, trimesh and Open3D give them) and gives exactly what the strict call gives on float32 and
int32, and Plan stays strict. Prints 'N passed, N failed' and exits non-zero on a failure."""
import sys

import numpy as np

import loopsub

passed, failed = 0, []


def check(condition, what):
    global passed
    if condition:
        passed += 1
        print(f"  ok    {what}")
    else:
        failed.append(what)
        print(f"  FAIL  {what}")


check("site-packages" in loopsub.__file__ and loopsub._loopsub.__name__ == "loopsub._loopsub",
      f"import loopsub finds the installed package ({loopsub.__file__}), the native module inside it")

check(issubclass(loopsub.InputError, ValueError) and loopsub.InputError is loopsub._loopsub.InputError
      and loopsub.diagnose is loopsub._loopsub.diagnose,
      "the core's InputError (a ValueError) and diagnose are the package's")

positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=np.float64) + 0.1
triangles = np.array([[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]], dtype=np.int64)
creases = np.array([[0, 1]], dtype=np.int64)
converted = loopsub.subdivide(positions, triangles, 2, rules="opensubdiv", crease_edges=creases,
                              crease_sharpness=[2.5])
strict = loopsub._loopsub.subdivide(positions.astype(np.float32), triangles.astype(np.int32), 2, rules="opensubdiv",
                                    crease_edges=creases.astype(np.int32),
                                    crease_sharpness=np.array([2.5], np.float32))
check(np.array_equal(converted["positions"], strict["positions"])
      and np.array_equal(converted["triangles"], strict["triangles"]),
      "float64 positions and int64 faces and tags give exactly the float32 / int32 result")
check(converted["positions"].dtype == np.float32 and converted["triangles"].dtype == np.int32,
      "the result has the core's types")
check(np.array_equal(loopsub.subdivide(positions.tolist(), triangles.tolist(), 1)["positions"],
                     loopsub.subdivide(positions, triangles, 1)["positions"]),
      "plain lists are accepted too")
check(np.array_equal(loopsub.subdivide(np.asfortranarray(positions), triangles[:, :], 1)["positions"],
                     loopsub.subdivide(positions, triangles, 1)["positions"]),
      "non-contiguous (Fortran-ordered) arrays are accepted")

for bad, error, what in ((triangles + 2 ** 33, ValueError, "an index past 32 bits"),
                         (triangles.astype(np.float64), TypeError, "float faces")):
    try:
        loopsub.subdivide(positions, bad, 1)
        check(False, f"{what} is refused")
    except error as exception:
        check(True, f"{what} is refused: {exception}")
try:
    loopsub.Plan(triangles, len(positions), 1)
    check(False, "Plan stays strict: int64 faces are refused, not copied")
except (TypeError, ValueError) as exception:
    check(True, f"Plan stays strict: int64 faces are refused, not copied ({exception})")

check(set(loopsub.__all__) >= {"Plan", "Tessellation", "screen_space_rates", "subdivide", "option_names",
                               "weld_corner_values"}
      and loopsub.option_names()["rules"] == ("hoppe94", "opensubdiv"),
      "the package offers the core's option names and its corner welding")

print(f"{passed} passed, {len(failed)} failed")
sys.exit(1 if failed else 0)
