"""Draws the preview in the 3D viewport with the gpu module. Imported only when Blender has a display (the gpu module
does not exist in background mode)."""
import bpy
import gpu
import numpy as np
from gpu_extras.batch import batch_for_shader

from . import compat, geometry, preview

# Lit from a fixed direction in object space: enough to read the shape, without per-frame work.
_LIGHT = np.array([0.32, -0.45, 0.83], dtype=np.float32) / np.linalg.norm([0.32, -0.45, 0.83])
_SURFACE_COLOR = np.array([0.8, 0.8, 0.8, 1.0], dtype=np.float32)
_WIRE_COLOR = (0.0, 0.0, 0.0, 0.35)

_batches = {}  # object name -> (entry version, surface batch, wire batch)


def _build(item, smooth_shader, flat_shader):
    shade = 0.35 + 0.65 * np.abs(item.normals @ _LIGHT)
    colors = np.empty((len(shade), 4), dtype=np.float32)
    colors[:, :3] = _SURFACE_COLOR[:3] * shade[:, None]
    colors[:, 3] = 1.0
    surface = batch_for_shader(smooth_shader, 'TRIS', {"pos": item.positions, "color": colors},
                               indices=item.triangles)
    keys = np.unique(geometry.edge_keys(item.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), len(item.positions)))
    edges = np.stack([keys // len(item.positions), keys % len(item.positions)], axis=1).astype(np.int32)
    wire = batch_for_shader(flat_shader, 'LINES', {"pos": item.positions}, indices=edges)
    return item.version, surface, wire


def draw(entries):
    smooth_shader = gpu.shader.from_builtin(compat.builtin_shader_name('SMOOTH_COLOR'))
    flat_shader = gpu.shader.from_builtin(compat.builtin_shader_name('UNIFORM_COLOR'))
    gpu.state.depth_test_set('LESS_EQUAL')
    gpu.state.depth_mask_set(True)
    gpu.state.blend_set('ALPHA')
    for obj in bpy.context.visible_objects:
        item = entries.get(obj.name)
        if not preview.wanted(obj) or item is None or item.positions is None:
            continue
        cached = _batches.get(obj.name)
        if cached is None or cached[0] != item.version:
            cached = _batches[obj.name] = _build(item, smooth_shader, flat_shader)
        with gpu.matrix.push_pop():
            gpu.matrix.multiply_matrix(obj.matrix_world)
            cached[1].draw(smooth_shader)
            flat_shader.bind()
            flat_shader.uniform_float("color", _WIRE_COLOR)
            cached[2].draw(flat_shader)
    for name in [name for name in _batches if name not in entries]:
        del _batches[name]
    gpu.state.blend_set('NONE')
    gpu.state.depth_mask_set(False)
    gpu.state.depth_test_set('NONE')


def release():
    _batches.clear()
