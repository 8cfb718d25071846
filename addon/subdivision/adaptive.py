"""Adaptive Subdivision: the view an entry is cut for, the rates it gives the cage's edges, and the tessellation.

A render and Apply take the scene camera at the render's resolution. The viewport takes the view of the largest 3D
Viewport (which is the camera's when it looks through it), or the scene camera where no 3D Viewport is open
(background mode). The viewport's result follows the view once the view has stopped moving (live._watch_views): a
tessellation is made again only where the rates change.
"""
import bpy
import numpy as np

from .. import native
from ..model import geometry, memory
from ..native import LoopSubError
from .cage import core_notes, counted
from .refinement import TessellationOutput


class View:
    """A camera as the core reads it: world to clip space (4 x 4, OpenGL's convention) and the viewport's size in
    pixels."""

    def __init__(self, world_to_clip, size):
        self.world_to_clip = np.asarray(world_to_clip, dtype=np.float32)
        self.size = size

    def __eq__(self, other):
        return (isinstance(other, View) and self.size == other.size
                and np.array_equal(self.world_to_clip, other.world_to_clip))


def scene_view(scene, depsgraph):
    """The scene camera at the render's resolution (its percentage and pixel aspect too), as evaluated in depsgraph
    (an animated camera where the frame has it)."""
    if scene.camera is None:
        raise LoopSubError("Adaptive Subdivision needs a scene camera")
    render = scene.render
    scale = render.resolution_percentage / 100
    width, height = max(1, round(render.resolution_x * scale)), max(1, round(render.resolution_y * scale))
    camera = scene.camera.evaluated_get(depsgraph)
    projection = camera.calc_matrix_camera(depsgraph, x=width, y=height, scale_x=render.pixel_aspect_x,
                                           scale_y=render.pixel_aspect_y)
    return View(projection @ camera.matrix_world.inverted(), (width, height))


def viewport_view(window_manager):
    """The view of the largest 3D Viewport of any window, None where none is open."""
    largest, view = 0, None
    for window in window_manager.windows if window_manager is not None else ():
        for area in window.screen.areas if window.screen is not None else ():
            space = area.spaces.active
            if area.type != 'VIEW_3D' or space.region_3d is None:
                continue
            for region in area.regions:
                if region.type == 'WINDOW' and region.width * region.height > largest:
                    largest = region.width * region.height
                    view = View(space.region_3d.perspective_matrix, (region.width, region.height))
    return view


def view_for(scene, depsgraph, render):
    """The view an entry is cut for: a render's (and Apply's) the scene camera, the viewport's its largest 3D
    Viewport's."""
    view = None if render or bpy.app.background else viewport_view(bpy.context.window_manager)
    return view or scene_view(scene, depsgraph)


def rates(cage, options, view, matrix_world):
    """(edges, rates) of a cage (of an object with matrix_world) seen from view, at the options' dicing rate."""
    object_to_clip = view.world_to_clip @ np.asarray(matrix_world, dtype=np.float32)
    return native.screen_space_rates(cage.positions, cage.triangles, object_to_clip, view.size, options)


def check_memory(source, edge_rates):
    """Whether the tessellation of source's cage at edge_rates fits: raises LoopSubError, saying what it would need
    and what is free, where Blender's side of the result (counted as cage.check_memory counts a level's) and the
    core's, at TESSELLATION_BYTES_PER_TRIANGLE, do not. Returns the MemoryBudget the core's own count (which knows how
    many triangles it refines through plans, at several times a patch's memory) must then fit."""
    cage = source.cage
    edges, segments = edge_rates
    sides = cage.triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    inner = segments[geometry.lookup_edges(edges, sides, cage.num_vertices)].reshape(-1, 3).max(axis=1)
    inner = inner.astype(np.int64)
    triangles = int(np.sum(inner * inner))
    vertices = cage.num_vertices + int(np.sum(segments - 1)) + int(np.sum((inner - 1) * (inner - 2) // 2))
    counts = (vertices, vertices + triangles, triangles)
    mesh = source.mesh
    product = memory.TESSELLATION_BYTES_PER_TRIANGLE * triangles * (1 + len(mesh.uv_layers))  # a UV map is cut too
    required = memory.estimate_output_bytes(counts, product, version=bpy.app.version, drawn=not bpy.app.background,
                                            **source.contents())
    subject = f"Adaptive Subdivision at {source.options.dicing_rate:g} px ({counted(triangles, 'triangle')})"
    budget = MemoryBudget(required - product, memory.available_bytes(), subject)
    if not memory.fits(required, budget.available):
        raise LoopSubError(memory.describe(required, budget.available, budget.subject))
    return budget


class MemoryBudget:
    """What a tessellation may use: blender_bytes, Blender's side of the result, come off what is available (None:
    unknown) and the reserve; the core gets the rest (core_limit) and refuses past it."""

    def __init__(self, blender_bytes, available, subject):
        self.blender_bytes, self.available, self.subject = blender_bytes, available, subject

    def core_limit(self):
        if self.available is None:
            return None
        return self.available - memory.reserve_bytes(self.available) - self.blender_bytes

    def refusal(self, core_bytes):
        """The LoopSubError of a core that counted core_bytes for itself, past core_limit()."""
        return LoopSubError(memory.describe(self.blender_bytes + core_bytes, self.available, self.subject))


def tessellate(source, edge_rates, reuse=None):
    """The TessellationOutput of source's cage at edge_rates, within the memory left (check_memory); reuse: an
    earlier cut's input_topology (native.build_tessellation)."""
    cage, options = source.cage, source.options
    budget = check_memory(source, edge_rates)
    try:
        tessellation = native.build_tessellation(cage.triangles, cage.num_vertices, edge_rates, options,
                                                 cage.tags(options), source.cones,
                                                 [indices for indices, _ in source.uv_layers], budget.core_limit(),
                                                 reuse)
    except LoopSubError as error:
        core_bytes = getattr(error.__cause__, "required_bytes", None)
        if not isinstance(error.__cause__, MemoryError) or core_bytes is None:
            raise source.explain(error) from error
        raise budget.refusal(core_bytes) from error
    output = TessellationOutput(tessellation, cage, options)
    source.messages = source.messages + core_notes(source.name, output.notes)
    return output
