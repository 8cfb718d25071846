"""Access to the native core (_loopsub, built by scripts/setup.sh into this package).

The module is imported on first use, so that the add-on registers and reports a missing build instead of failing to
load. Every error of the core becomes a LoopSubError, which the operators turn into an error report.
"""
import importlib.machinery
import importlib.util
import os
import shutil

import numpy as np


class LoopSubError(Exception):
    """A problem the artist can act on; the message is shown as a Blender report. problem: where the core's checks
    refused the input, what they found (an InputError's attributes: kind, element, index, ...), else None."""

    def __init__(self, message, problem=None):
        super().__init__(message)
        self.problem = problem


def _refused(error):
    """The LoopSubError of an error the core raised."""
    return LoopSubError(str(error), error if getattr(error, "kind", None) is not None else None)


# Where the module is loaded from: a copy in this folder (Blender's temporary folder of the session, which it empties
# on quitting; set on registering), not the installed file. Blender 3.4's Install writes a newer zip's files over the
# installed ones, and a module whose file is rewritten while it is loaded crashes the process on its next call; a
# copy is never written again. None: the installed file (tests without Blender).
private_folder = None
_module = None


def load():
    global _module
    if _module is None:
        _module = _import()
    return _module


def _import():
    here = os.path.dirname(os.path.abspath(__file__))
    installed = next((path for path in (os.path.join(here, "_loopsub" + suffix)
                                        for suffix in importlib.machinery.EXTENSION_SUFFIXES)
                      if os.path.isfile(path)), None)
    try:
        if installed is None:
            raise ImportError(f"no _loopsub module for this Python in {here}")
        return _import_from(_private_copy(installed) or installed)
    except (ImportError, OSError) as error:
        raise LoopSubError("The native Loop subdivision module is missing or does not load "
                           f"({error}); build it with scripts/setup.sh") from error


def _private_copy(installed):
    """A copy of the installed module in private_folder, named by the installed file's size and time (an update's
    module gets a folder of its own); None where there is no such folder or it cannot be written."""
    if not private_folder:
        return None
    status = os.stat(installed)
    folder = os.path.join(private_folder, f"loop_subdivision-{status.st_size}-{status.st_mtime_ns}")
    copy = os.path.join(folder, os.path.basename(installed))
    try:
        if not os.path.isfile(copy):
            os.makedirs(folder, exist_ok=True)
            shutil.copyfile(installed, copy + ".part")
            os.replace(copy + ".part", copy)
    except OSError:
        return None
    return copy


def _import_from(path):
    spec = importlib.util.spec_from_file_location(f"{__package__}._loopsub", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def build_plan(triangles, num_vertices, levels, options, tags, cone_vertices, face_varying_indices=()):
    """A reusable plan (all topology work) for the triangulated cage.

    tags: the dict of geometry.crease_tags (empty arrays when creases are off); cone_vertices: int32 indices, used by
    the seed's rules only (OpenSubdiv has no cones); face_varying_indices: one (M, 3) int32 array per UV map
    (weld_corner_values), refined by the options' UV Smooth.
    """
    if options.rules != 'HOPPE94':
        cone_vertices = np.zeros(0, dtype=np.int32)
    try:
        return load().Plan(triangles, num_vertices, levels, cone_vertices=cone_vertices,
                           face_varying_indices=list(face_varying_indices) or None,
                           **tags, **options.plan_keywords())
    # The bindings raise ValueError/TypeError for bad input, RuntimeError/MemoryError for limits.
    except (ValueError, TypeError, RuntimeError, MemoryError, OverflowError) as error:
        raise _refused(error) from error


def build_tessellation(triangles, num_vertices, rates, options, tags, cone_vertices, face_varying_indices=(),
                       memory_limit=None, reuse=None):
    """The limit surface of the triangulated cage cut by rates ((edges (K, 2), rates (K,)) from screen_space_rates),
    with the options' rules, tags and UV maps (refined by UV Smooth) as for build_plan; memory_limit: bytes it may use
    (None: the core's default); reuse: an earlier cut's input_topology (the core takes it where the cage, its tags
    and rules are the same)."""
    if options.rules != 'HOPPE94':
        cone_vertices = np.zeros(0, dtype=np.int32)
    edges, edge_rates = rates
    limit = {} if memory_limit is None else {"memory_limit_bytes": max(0, int(memory_limit))}
    return run(load().Tessellation, triangles, num_vertices, edges=edges, edge_rates=edge_rates,
               cone_vertices=cone_vertices, face_varying_indices=list(face_varying_indices) or None, reuse=reuse,
               **tags, **options.tessellation_keywords(), **limit)


def screen_space_rates(positions, triangles, object_to_clip, viewport, options):
    """Each cage edge's rate as the camera (object_to_clip (4, 4), viewport (width, height) in pixels) sees it at the
    options' dicing rate, measure and maximum: (edges (E, 2) int32, rates (E,) int32)."""
    return run(load().screen_space_rates, positions, triangles, np.ascontiguousarray(object_to_clip, np.float32),
               viewport, **options.rate_keywords())


def weld_corner_values(triangles, num_vertices, corner_values):
    """One face-varying layer from per-corner values (a UV map read per triangle corner, (T, 3, C) float32): the
    core's weld. Returns (indices (T, 3) int32, values (V, C) float32). Corners of a vertex with equal values share
    one; a value dragged without splitting or joining corners keeps every index, so the live entry keeps its plan."""
    return run(load().weld_corner_values, triangles, num_vertices, np.ascontiguousarray(corner_values, np.float32))


def estimate_plan_bytes(vertices, edges, triangles, levels, vertex_channels=3):
    """The core's own estimate of a plan for these counts and one evaluation of vertex_channels floats a vertex."""
    return run(load().estimate_plan_bytes, vertices, triangles, levels, vertex_channels, edges)


def diagnose(triangles, num_vertices, **values):
    """Everything the core's checks find in these triangles and values (positions: per-vertex channels; face_varying:
    per-corner values), errors first, then notes: the items of _loopsub.diagnose (kind, element, index, corner,
    layer, channel, ...)."""
    return run(load().diagnose, triangles, num_vertices, **values)


def refusal(problem):
    """The LoopSubError of a problem diagnose listed, as the core would raise it."""
    return LoopSubError(problem.message, problem)


def run(call, *args, **keywords):
    """Calls a plan method, turning the core's errors into LoopSubError."""
    try:
        return call(*args, **keywords)
    except (ValueError, TypeError, RuntimeError, MemoryError, OverflowError) as error:
        raise _refused(error) from error
