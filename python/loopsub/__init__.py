"""Loop subdivision of triangle meshes with creases: the native core (``loopsub._loopsub``) for pipelines.

``Plan``, ``Tessellation`` and ``_loopsub.subdivide`` are strict and zero-copy: float32 positions and int32 indices,
C-contiguous, used in place. ``subdivide`` here takes what numpy, trimesh and Open3D hand over (float64 positions,
int64 faces, lists, non-contiguous views) and converts each array once to the core's types before the same call. See
docs/python.md.
"""
import numpy as np

from ._loopsub import (INFINITE_SHARPNESS, VERTEX_TYPES, InputError, InputTopology, Plan, Tessellation, best_kernel,
                       diagnose, option_names, screen_space_rates, weld_corner_values)
from ._loopsub import subdivide as _subdivide_strict

__all__ = ["INFINITE_SHARPNESS", "VERTEX_TYPES", "InputError", "InputTopology", "Plan", "Tessellation", "best_kernel",
           "diagnose", "option_names", "screen_space_rates", "subdivide", "weld_corner_values"]

_INDEX_ARGUMENTS = ("crease_edges", "corner_vertices", "cone_vertices", "hole_triangles")
_VALUE_ARGUMENTS = ("crease_sharpness", "corner_sharpness")


def _indices(name, values):
    array = np.asarray(values)
    if array.size and not np.issubdtype(array.dtype, np.integer):
        raise TypeError(f"{name} must hold integers, got {array.dtype}")
    if array.size and (array.min() < np.iinfo(np.int32).min or array.max() > np.iinfo(np.int32).max):
        raise ValueError(f"{name} holds an index outside the 32-bit range the core uses")
    return np.ascontiguousarray(array, dtype=np.int32)


def _floats(name, values):
    array = np.asarray(values)
    if array.size and not (np.issubdtype(array.dtype, np.floating) or np.issubdtype(array.dtype, np.integer)):
        raise TypeError(f"{name} must hold numbers, got {array.dtype}")
    return np.ascontiguousarray(array, dtype=np.float32)


def subdivide(positions, triangles, levels=1, **options):
    """Subdivides a mesh in one call, as ``loopsub._loopsub.subdivide`` (same options and result), after converting
    positions, face-varying and vertex data to float32 and triangles and tag indices to int32, once each. Indices
    must fit 32 bits; values outside float32's range become infinite and are then refused by the core."""
    for name in _INDEX_ARGUMENTS:
        if options.get(name) is not None:
            options[name] = _indices(name, options[name])
    if options.get("face_varying_indices") is not None:
        options["face_varying_indices"] = [_indices(f"face_varying_indices[{k}]", layer)
                                           for k, layer in enumerate(options["face_varying_indices"])]
    for name in _VALUE_ARGUMENTS:
        if options.get(name) is not None:
            options[name] = _floats(name, options[name])
    for name in ("vertex_data", "face_varying"):
        value = options.get(name)
        if isinstance(value, dict):
            options[name] = {key: _floats(f"{name}[{key!r}]", item) for key, item in value.items()}
        elif value is not None:
            options[name] = _floats(name, value)
    return _subdivide_strict(_floats("positions", positions), _indices("triangles", triangles), levels, **options)
