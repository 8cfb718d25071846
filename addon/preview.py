"""Live preview of the Loop subdivision result, kept per object and refreshed on depsgraph updates.

The core's plan holds all topology work, so it is kept while the cage's triangles, tags and settings stay the same and
only re-evaluated with the new positions (moving vertices in Edit Mode costs one evaluation). Drawing is in
preview_draw, which imports gpu and is loaded only when Blender has a display: this module runs in background mode too.
"""
import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import geometry, mesh_data, native
from .native import LoopSubError


class Entry:
    """One object's preview: the plan with what it was built from, and the latest result."""

    def __init__(self):
        self.plan = None
        self.built_from = None  # (options, triangles, tag arrays..., cones) of the plan
        self.plan_builds = 0  # how many plans this entry has built (the tests check the re-use)
        self.positions = None
        self.triangles = None
        self.normals = None
        self.version = 0  # bumped at each new result, so the drawing knows when to rebuild its buffers
        self.error = ""


_entries = {}
_draw_handle = None


def wanted(obj):
    return (obj is not None and obj.type == 'MESH' and obj.loop_subdivision.enabled
            and obj.loop_subdivision.show_viewport)


def entry(obj):
    return _entries.get(obj.name)


def _same(built_from, current):
    return (built_from is not None and built_from[0] == current[0]
            and all(np.array_equal(a, b) for a, b in zip(built_from[1:], current[1:])))


def _cage_mesh(obj, depsgraph):
    """The cage as the artist sees it: in Edit Mode only the evaluated mesh follows the edits (the original data is
    written back on leaving Edit Mode), so that is read then; otherwise the object's own mesh, as apply uses it."""
    if obj.mode == 'EDIT' and depsgraph is not None:
        evaluated = obj.evaluated_get(depsgraph)
        return evaluated, evaluated.to_mesh()
    return None, obj.data


def refresh(obj, depsgraph=None):
    settings = obj.loop_subdivision
    current = _entries.setdefault(obj.name, Entry())
    evaluated, mesh = _cage_mesh(obj, depsgraph)
    try:
        options = settings.options(levels=settings.preview_levels)
        cage = mesh_data.Cage(mesh)
        cage.validate(obj.name)
        cone_index = mesh_data.cone_group_index(obj, options)
        weights = mesh_data.read_vertex_groups(mesh, cone_index + 1) if cone_index is not None else None
        cones = mesh_data.cone_vertices(weights, cone_index)
        tags = cage.tags(options)
        key = (options, cage.triangles, *tags.values(), cones)
        if not _same(current.built_from, key):
            current.plan = cage.plan(options, options.levels, cones)
            current.built_from = key
            current.plan_builds += 1
        positions = native.run(current.plan.evaluate, cage.positions)
        current.triangles = current.plan.triangles
        current.positions = positions
        current.normals = geometry.vertex_normals(positions, current.triangles)
        current.error = ""
    except LoopSubError as error:  # shown in the panel, as Blender shows a modifier's error
        current.error = str(error)
        current.positions = None
    finally:
        if evaluated is not None:
            evaluated.to_mesh_clear()
    current.version += 1
    _redraw()


def settings_changed(obj):
    """Property update callback: follow the settings and keep the cage shown as a wireframe under the preview."""
    settings = obj.loop_subdivision
    if wanted(obj):
        if obj.display_type != 'WIRE':
            settings.cage_display_type = obj.display_type
            obj.display_type = 'WIRE'
        refresh(obj)
    else:
        if settings.cage_display_type:
            obj.display_type = settings.cage_display_type
            settings.cage_display_type = ""
        _entries.pop(obj.name, None)
        _redraw()


def _redraw():
    window_manager = bpy.context.window_manager
    for window in window_manager.windows if window_manager else ():
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                area.tag_redraw()


@persistent
def _on_depsgraph_update(scene, depsgraph):
    for name in [name for name in _entries if not wanted(bpy.data.objects.get(name))]:
        del _entries[name]  # deleted, renamed or switched off
    for update in depsgraph.updates:
        if isinstance(update.id, bpy.types.Object) and update.is_updated_geometry:
            obj = update.id.original
            if wanted(obj):
                refresh(obj, depsgraph)


def _refresh_all():
    """Previews for every object that has the entry: after a file loads, or when the add-on is enabled in a session
    that has such objects (nothing would trigger them until the next edit)."""
    for obj in bpy.data.objects:
        if wanted(obj):
            refresh(obj)


@persistent
def _on_load(_):
    # Names may now belong to other objects: start afresh.
    _entries.clear()
    _refresh_all()


def register():
    global _draw_handle
    bpy.app.handlers.depsgraph_update_post.append(_on_depsgraph_update)
    bpy.app.handlers.load_post.append(_on_load)
    # Add-ons register while bpy.data is not yet accessible (at start-up): look once the event loop runs.
    bpy.app.timers.register(_refresh_all, first_interval=0.0)
    if not bpy.app.background:
        from . import preview_draw
        _draw_handle = bpy.types.SpaceView3D.draw_handler_add(preview_draw.draw, (_entries,), 'WINDOW', 'POST_VIEW')


def unregister():
    global _draw_handle
    if _draw_handle is not None:
        bpy.types.SpaceView3D.draw_handler_remove(_draw_handle, 'WINDOW')
        _draw_handle = None
        from . import preview_draw
        preview_draw.release()
    if bpy.app.timers.is_registered(_refresh_all):
        bpy.app.timers.unregister(_refresh_all)
    bpy.app.handlers.depsgraph_update_post.remove(_on_depsgraph_update)
    bpy.app.handlers.load_post.remove(_on_load)
    _entries.clear()
