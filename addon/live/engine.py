"""Keeps each Loop Subdivision entry's result current: after edits (depsgraph updates), on frame changes (playback),
before every frame a render evaluates (at Render levels), and when settings change.

The input is the object evaluated up to the cache. Blender evaluates a stack as a whole and shows an add-on no
intermediate mesh, so the entry and every active modifier below it are switched off for one evaluation of the view
layer's depsgraph, whose result is the input, and switched on again once the helper holds the new subdivision. A guard
keeps the handlers from reacting to the updates this makes.

Renders read their input from the view layer's depsgraph too (so modifiers above the entry act with their viewport
settings): Blender 3.4 does not re-evaluate a render depsgraph reliably when a modifier is switched off and on from
Python. A render from the interface runs its handlers in the render thread, which must not evaluate the view layer:
it asks the main thread to write the results and waits.

The core's plan (all topology work) is kept per object while the input's triangles, tags, UV seams and settings
(Use Limit Surface and UV Smooth included) stay the same; then only the vertex and face-varying values are refined
again and written into the result in place.

With Adaptive Subdivision, the result is cut for a view (adaptive.py) instead of levels, and kept while the cage's
triangles, tags and settings and the rates of its edges stay the same: moving the object or its camera changes the
rates, and renders use the scene camera. The viewport's view is polled (_watch_views), since changing it is no
update of any data.

With Use Limit Surface, every update (an edit, a frame of playback, a setting's change, a render) writes the limit
normals into the result as custom normals, the same ones Apply writes, the cheapest way the version offers
(normals.write_limit_normals; docs/addon.md, Normals).

After each update (not on frame changes), after a render, before saving and after loading, stack.collect() frees the
helpers, results and node group that no live entry uses any more: a deleted object or a removed entry leaves nothing.
A file holds the cage and the settings, not the results (unless Store Result asks), which are made again on loading.
"""
import contextlib

import bpy
import numpy as np

from ..blender import mesh_arrays, stack
from ..native import LoopSubError
from ..subdivision import adaptive, cage, refinement, result
from ..subdivision.refinement import PlanOutput, TessellationOutput
from . import activity, status


class Cache:
    """What one object's entry keeps between updates."""

    def __init__(self):
        self.output = None  # the result's structure: output.PlanOutput, or TessellationOutput (Adaptive Subdivision)
        self.plan_key = None
        self.layout_key = None
        self.result = None  # name of the helper mesh built for plan_key and layout_key
        self.inputs = None  # the refined channels' inputs last written, to skip updates that change nothing
        self.blender_corners = None  # the result's corners that keep Blender's own normal (result.build_mesh)
        self.plan_builds = 0  # plans and tessellations built so far (tests check that edits reuse them)
        self.cut = None  # Adaptive Subdivision: the (cage, options, object matrix) of the last cut, in the viewport
        self.error = ""
        self.messages = []  # notes on the cage of the current plan: (level, text) as in Operator.report
        self.options = None  # the settings of the last viewport update (_changed_settings)
        self.base = None  # the Cache of the Base Result, where the entry is not first (_refresh_base)


_caches = {}


def cache_of(obj):
    return _caches.get(obj.name)


def _equal(a, b):
    return a is not None and len(a) == len(b) and all(
        np.array_equal(x, y) if isinstance(x, np.ndarray) or isinstance(y, np.ndarray) else x == y
        for x, y in zip(a, b))


def refresh(obj, depsgraph, render=False, base_changed=True):
    """Brings obj's entry up to date: its input read from depsgraph (the view layer's), subdivided at Levels Viewport,
    or at Render levels for a render; and, in the viewport, its Base Result where the entry is not first, made anew
    unless base_changed says that neither the object's own mesh nor the settings changed."""
    modifier = stack.entry(obj)
    if modifier is None or not activity.may_refresh():
        return
    if not (modifier.show_render if render else modifier.show_viewport):
        return
    if obj.library is not None:
        return _linked(obj, modifier)
    helper = stack.helper_of(obj, modifier)
    first = stack.is_first(obj, modifier)
    options = obj.loop_subdivision.options(render=render)
    cache = _caches.setdefault(obj.name, Cache())
    if not render:
        cache.options = options
    with activity.writing():
        with _input(obj, modifier, depsgraph) as (evaluated, mesh):
            # Read first: the operator that writes vertex groups (result._write_vertex_groups) evaluates the
            # depsgraph, which frees `mesh`.
            own_mesh = not render and not first and _is_own_mesh(mesh, obj)
            _write(cache, obj, evaluated, mesh, helper, options, depsgraph, render)
        if not render:
            _refresh_base(obj, modifier, first, cache, options, depsgraph, base_changed, own_mesh)


@contextlib.contextmanager
def _input(obj, modifier, depsgraph):
    """(the evaluated object, its mesh) up to the entry: the entry and every active modifier below it switched off for
    one evaluation, and on again after."""
    index = list(obj.modifiers).index(modifier)
    switched = [other for other in obj.modifiers[index:] if other.show_viewport]
    try:
        for other in switched:
            other.show_viewport = False
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        try:
            yield evaluated, evaluated.to_mesh()
        finally:
            evaluated.to_mesh_clear()
    finally:
        for other in switched:
            other.show_viewport = True
        depsgraph.update()


def _is_own_mesh(mesh, obj):
    """Whether the input mesh is the object's own in points, positions and faces (the modifiers above change none of
    them: a rig at rest); not asked in Edit Mode, where the object's mesh is not the edited one."""
    own = obj.data
    if obj.mode == 'EDIT' or len(mesh.vertices) != len(own.vertices) or len(mesh.polygons) != len(own.polygons):
        return False
    return np.array_equal(mesh_arrays.read_positions(mesh), mesh_arrays.read_positions(own))


def _refresh_base(obj, modifier, first, cache, options, depsgraph, changed, own_mesh):
    """The Base Result (stack.BASE_SOCKET): where modifiers above the entry act, the subdivision of the object's own
    mesh, which Blender's own Apply gives (it evaluates the entry on that mesh alone), made anew where that mesh or
    the settings changed; none where the entry is first, whose input is that mesh. Where the stack's input is that
    mesh itself (own_mesh), the node group shows the result of the stack: the modifiers above may change what the
    Base Result cannot tell (shading, creases), and renders show Render levels. Kept as it was in Edit Mode, where
    the object's mesh is not the edited one: leaving Edit Mode updates the mesh, and so the Base Result."""
    if first:
        cache.base = None
        stack.clear_input(modifier, stack.BASE_SOCKET)  # collect() frees the helper
        return
    if obj.mode == 'EDIT':
        return
    helper = stack.helper_of(obj, modifier, socket=stack.BASE_SOCKET)
    if cache.base is None or changed:
        cache.base = cache.base or Cache()
        # Its refusals are not the entry's (the modifiers above may take out what is refused): Blender's Apply gets
        # the mesh as it is then.
        _write(cache.base, obj, obj, obj.data, helper, options, depsgraph, render=False, tell=False)
        stack.keep_base_input(helper, obj.data)
    stack.show_base(helper, not own_mesh)


def _write(cache, obj, evaluated, mesh, helper, options, depsgraph, render, tell=True):
    try:
        if options.levels == 0 and not options.use_adaptive:
            raise _PassThrough
        source = cage.Source(obj, mesh, options, cache.plan_key[1] if cache.plan_key else None)
        # A result no larger than the one shown fitted before; a larger one is checked against the memory left.
        shown = len(helper.data.polygons) if cache.result == helper.data.name else 0
        if not options.use_adaptive and (len(mesh.loops) - 2 * len(mesh.polygons)) * 4 ** options.levels > shown:
            cage.check_memory(source)
        if options.use_adaptive:
            view = adaptive.view_for(depsgraph.scene, depsgraph, render)
            edge_rates = adaptive.rates(source.cage, options, view, evaluated.matrix_world)
            cache.cut = None if render else (source.cage, options, evaluated.matrix_world.copy())
            plan_key = (*source.plan_key(), *edge_rates)
        else:
            cache.cut = None
            plan_key = source.plan_key()
        if not _equal(cache.plan_key, plan_key):
            # The old plan is of another topology: it goes before the new one is built, so that a large result's two
            # plans are never held at once, and the new one reuses its memory. A new cut of the same cage keeps the
            # old one's work on the cage alone (it holds nothing of the result).
            reuse = cache.output.tessellation.input_topology if isinstance(cache.output, TessellationOutput) else None
            cache.output = cache.plan_key = None
            if options.use_adaptive:
                cache.output = adaptive.tessellate(source, edge_rates, reuse)
            else:
                cache.output = PlanOutput(source.plan())
            # A new structure needs a new result, even where its counts and layout are the old one's (an edge
            # rotated in Edit Mode; rates traded between edges).
            cache.plan_key, cache.inputs, cache.layout_key = plan_key, None, None
            cache.plan_builds += 1
            cache.messages = source.messages
        inputs = source.inputs()
        layout_key = source.layout_key()
        in_place = (cache.result == helper.data.name and _equal(cache.layout_key, layout_key)
                    and len(helper.data.vertices) == cache.output.num_vertices)
        if in_place and inputs.equals(cache.inputs):
            return
        if in_place:
            refined = refinement.refine(cache.output, source, written=cache.inputs)
            result.update_mesh(helper.data, source, refined, cache.blender_corners)
        else:
            old = helper.data
            _swap(helper, old, result.build_mesh(source, cache.output, helper.name))
            cache.result, cache.layout_key = helper.data.name, layout_key
            cache.blender_corners = source.blender_corners
        cache.inputs = inputs
        if cache.error:
            status.clear()  # what was wrong is mended: the status bar no longer says otherwise
        cache.error = ""
    except (LoopSubError, _PassThrough) as problem:
        # As a modifier that cannot work: the input passes through unchanged, and the panel says why.
        if tell and cache.error != str(problem) and str(problem):
            # The add-on's own checks name the object already; the core's and the memory check's do not.
            status.tell(str(problem) if str(problem).startswith(f"{obj.name}: ") else f"{obj.name}: {problem}")
        cache.error = str(problem)
        cache.plan_key = cache.result = cache.inputs = cache.cut = None
        _swap(helper, helper.data, bpy.data.meshes.new_from_object(evaluated))


def _linked(obj, modifier):
    """An entry linked from another file is read-only here: it shows the result that file saved, or, where the file
    saved none (Store Result off, the default), its input, which the panel and the console say once, with the ways out.
    The result cannot be made here: the entry points at what its own file holds."""
    cache = _caches.setdefault(obj.name, Cache())
    if stack.is_helper(stack.modifier_input(modifier, stack.RESULT_SOCKET)) or cache.error:
        return
    cache.error = (f"Linked from {bpy.path.basename(obj.library.filepath)}, which keeps no result: turn on Store "
                   "Result there, or make a Library Override here")
    status.tell(f"{obj.name}: {cache.error}")


class _PassThrough(Exception):
    """Levels 0: the entry shows its input."""


def _swap(helper, old, mesh):
    mesh[stack.RESULT_TAG] = True  # collect() frees it once nothing uses it
    helper.data = mesh
    # A mesh replaced during a render stays (a render job may still read it) until collect() runs after the render,
    # found by its tag: not by name, which the result replacing it takes.
    if old is not None and old != mesh and old.users == 0 and not activity.rendering():
        bpy.data.meshes.remove(old)
    mesh.name = helper.name


def refresh_all(depsgraph=None, render=False):
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    for obj in [instance.original for instance in depsgraph.objects]:
        refresh(obj, depsgraph, render)


def settings_changed(obj):
    """Property update callback of the entry's settings."""
    if stack.entry(obj) is not None and not activity.rendering():
        refresh(obj, bpy.context.evaluated_depsgraph_get())


def _dropped():
    for name in [name for name in _caches if stack.entry(bpy.data.objects.get(name)) is None]:
        del _caches[name]  # deleted, renamed or without an entry


def collect():
    """Frees the helpers, results and node group that no live entry uses any more (stack.collect), and takes pasted
    helpers out of the scene (stack.unlink_helpers); not while a render job may read them."""
    if not activity.idle():
        return
    with activity.writing():  # the updates removing data makes are not edits
        stack.collect()
        stack.unlink_helpers()


def refresh_updated(depsgraph):
    """Refreshes the entries of the objects whose geometry this evaluation changed (edits, settings, animation)."""
    if not activity.idle():
        return
    _dropped()
    updated = {update.id.original for update in depsgraph.updates
               if isinstance(update.id, bpy.types.Object)
               and (update.is_updated_geometry or update.is_updated_transform and is_cut(update.id.original))}
    changed_settings = _changed_settings()
    updated |= _cut_for_camera(depsgraph) | changed_settings
    # A Base Result is made anew when the object's own mesh or the settings changed: not on the frames of an
    # animation in the modifiers above (a rig's playback).
    changed_meshes = {update.id.original for update in depsgraph.updates if isinstance(update.id, bpy.types.Mesh)}
    for obj in updated:
        stack.tidy(obj)  # a duplicated entry named as one, the helper's fields hidden
        if stack.keep_off_cage(obj):
            status.tell(f"{obj.name}: {status.ON_CAGE_REFUSAL}")
        refresh(obj, depsgraph, base_changed=obj.data in changed_meshes or obj in changed_settings)


def _changed_settings():
    """The objects whose entry's settings differ from those of its last viewport update: keyframed or driven ones (an
    animated Levels Viewport, as Subdivision Surface's can be), which a frame evaluates with no geometry update."""
    changed = set()
    for name, cache in _caches.items():
        obj = bpy.data.objects.get(name)
        if obj is not None and cache.options is not None and cache.options != obj.loop_subdivision.options():
            changed.add(obj)
    return changed


def is_cut(obj):
    """Whether obj's viewport result is cut by a view (Adaptive Subdivision): its rates follow its transform too."""
    cache = _caches.get(obj.name)
    return cache is not None and cache.cut is not None


def _cut_for_camera(depsgraph):
    """The objects whose viewport result the scene camera cut (Adaptive Subdivision without a 3D Viewport), where
    this evaluation moved the camera or changed its lens."""
    camera = depsgraph.scene.camera
    if not bpy.app.background or camera is None:
        return set()
    if not any(update.id.original in (camera, camera.data) for update in depsgraph.updates):
        return set()
    return {obj for obj in (bpy.data.objects.get(name) for name in _caches) if obj is not None and is_cut(obj)}


def forget_results():
    """Undo restores the helpers' meshes as they were: the next result is built anew rather than written into one."""
    for cache in _caches.values():
        cache.result = cache.inputs = None


def forget_all():
    _caches.clear()


def follow_view(view):
    """Cuts again the viewport's adaptive entries whose rates differ in view (a settled viewport view)."""
    depsgraph = None
    for name, cache in list(_caches.items()):
        obj = bpy.data.objects.get(name)
        if cache.cut is None or obj is None or stack.entry(obj) is None:
            continue
        cut_cage, options, matrix_world = cache.cut
        if not _equal(cache.plan_key[-2:], adaptive.rates(cut_cage, options, view, matrix_world)):
            depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
            refresh(obj, depsgraph)
