"""Access to the native core (_loopsub, built by scripts/setup.sh into this package).

The module is imported on first use, so that the add-on registers and reports a missing build instead of failing to
load. Every error of the core becomes a LoopSubError, which the operators turn into an error report.
"""
import numpy as np


class LoopSubError(Exception):
    """A problem the artist can act on; the message is shown as a Blender report."""


def load():
    try:
        from . import _loopsub
    except ImportError as error:
        raise LoopSubError("The native Loop subdivision module is missing or does not load "
                           f"({error}); build it with scripts/setup.sh") from error
    return _loopsub


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
        raise LoopSubError(str(error)) from error


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


def run(call, *args, **keywords):
    """Calls a plan method, turning the core's errors into LoopSubError."""
    try:
        return call(*args, **keywords)
    except (ValueError, TypeError, RuntimeError, MemoryError, OverflowError) as error:
        raise LoopSubError(str(error)) from error
