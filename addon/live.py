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
import queue
import threading
import traceback

import bpy
import numpy as np
from bpy.app.handlers import persistent

from . import adaptive, cage, compat, result, stack
from .native import LoopSubError
from .output import PlanOutput, TessellationOutput


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
_busy = False
# From the start of a render job to its end: edits and frame changes of the interface then leave the helpers alone
# (the render job holds the scene; the work a render asks for is served on its request only).
_rendering = False


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
    global _busy
    modifier = stack.entry(obj)
    if modifier is None or _busy or _saving or not (modifier.show_render if render else modifier.show_viewport):
        return
    if obj.library is not None:
        return _linked(obj, modifier)
    options = obj.loop_subdivision.options(render=render)
    helper = stack.helper_of(obj, modifier)
    index = list(obj.modifiers).index(modifier)
    switched = [other for other in obj.modifiers[index:] if other.show_viewport]
    _busy = True
    try:
        for other in switched:
            other.show_viewport = False
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        try:
            cache = _caches.setdefault(obj.name, Cache())
            if not render:
                cache.options = options
            # Read first: the operator that writes vertex groups (result._write_vertex_groups) evaluates the
            # depsgraph, which frees `mesh`.
            own_mesh = not render and not stack.is_first(obj, modifier) and _is_own_mesh(mesh, obj)
            _write(cache, obj, evaluated, mesh, helper, options, depsgraph, render)
        finally:
            evaluated.to_mesh_clear()
    finally:
        for other in switched:
            other.show_viewport = True
        depsgraph.update()
        _busy = False
    if not render:
        _busy = True
        try:
            _refresh_base(obj, modifier, cache, options, depsgraph, base_changed, own_mesh)
        finally:
            _busy = False


def _is_own_mesh(mesh, obj):
    """Whether the input mesh is the object's own in points, positions and faces (the modifiers above change none of
    them: a rig at rest); not asked in Edit Mode, where the object's mesh is not the edited one."""
    own = obj.data
    if obj.mode == 'EDIT' or len(mesh.vertices) != len(own.vertices) or len(mesh.polygons) != len(own.polygons):
        return False
    return np.array_equal(compat.read_positions(mesh), compat.read_positions(own))


def _refresh_base(obj, modifier, cache, options, depsgraph, changed, own_mesh):
    """The Base Result (stack.BASE_SOCKET): where modifiers above the entry act, the subdivision of the object's own
    mesh, which Blender's own Apply gives (it evaluates the entry on that mesh alone), made anew where that mesh or
    the settings changed; none where the entry is first, whose input is that mesh. Where the stack's input is that
    mesh itself (own_mesh), the node group shows the result of the stack: the modifiers above may change what the
    Base Result cannot tell (shading, creases), and renders show Render levels. Kept as it was in Edit Mode, where
    the object's mesh is not the edited one: leaving Edit Mode updates the mesh, and so the Base Result."""
    if stack.is_first(obj, modifier):
        cache.base = None
        if compat.modifier_input(modifier, stack.BASE_SOCKET) is not None:
            compat.set_modifier_input(modifier, stack.BASE_SOCKET, None)  # collect() frees the helper
        return
    if obj.mode == 'EDIT':
        return
    helper = stack.helper_of(obj, modifier, socket=stack.BASE_SOCKET)
    if cache.base is None or changed:
        cache.base = cache.base or Cache()
        # Its refusals are not the entry's (the modifiers above may take out what is refused): Blender's Apply gets
        # the mesh as it is then.
        _write(cache.base, obj, obj, obj.data, helper, options, depsgraph, render=False, tell=False)
        stack.keep_base_input(helper, compat.read_positions(obj.data), len(obj.data.polygons))
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
        if in_place and _equal(cache.inputs, inputs):
            return
        if in_place:
            refined = cache.output.refine(source, written=cache.inputs)
            result.update_mesh(helper.data, source, refined, cache.blender_corners)
        else:
            old = helper.data
            _swap(helper, old, result.build_mesh(source, cache.output, helper.name))
            cache.result, cache.layout_key = helper.data.name, layout_key
            cache.blender_corners = source.blender_corners
        cache.inputs = inputs
        if cache.error:
            _clear_status()  # what was wrong is mended: the status bar no longer says otherwise
        cache.error = ""
    except (LoopSubError, _PassThrough) as problem:
        # As a modifier that cannot work: the input passes through unchanged, and the panel says why.
        if tell and cache.error != str(problem) and str(problem):
            # The add-on's own checks name the object already; the core's and the memory check's do not.
            _tell(str(problem) if str(problem).startswith(f"{obj.name}: ") else f"{obj.name}: {problem}")
        cache.error = str(problem)
        cache.plan_key = cache.result = cache.inputs = cache.cut = None
        _swap(helper, helper.data, bpy.data.meshes.new_from_object(evaluated))


_STATUS_SECONDS = 10.0
ON_CAGE_REFUSAL = "Loop Subdivision cannot adjust the edit cage to its result: the cage is drawn as it is"


# The workspaces whose status bar shows what _tell said, until _clear_status.
_told = set()


def _tell(text):
    """A refusal the artist should see beside the panel's note: in the status bar for a while, or until the entry
    works again (the interface), and on the console (renders and scripts from the command line)."""
    print(f"Loop Subdivision: {text}")
    if bpy.app.background or bpy.context.window_manager is None:
        return
    _told.update(window.workspace for window in bpy.context.window_manager.windows if window.workspace is not None)
    for workspace in _told:
        workspace.status_text_set(text)
    if bpy.app.timers.is_registered(_clear_status):
        bpy.app.timers.unregister(_clear_status)  # the newest message stays its full while
    bpy.app.timers.register(_clear_status, first_interval=_STATUS_SECONDS)


def _clear_status():
    for workspace in _told:
        try:
            workspace.status_text_set(None)
        except ReferenceError:
            pass  # a workspace deleted meanwhile
    _told.clear()


def _linked(obj, modifier):
    """An entry linked from another file is read-only here: it shows the result that file saved, or, where the file
    saved none (Store Result off, the default), its input, which the panel and the console say once, with the ways out.
    The result cannot be made here: the entry points at what its own file holds."""
    cache = _caches.setdefault(obj.name, Cache())
    if stack.is_helper(compat.modifier_input(modifier, stack.RESULT_SOCKET)) or cache.error:
        return
    cache.error = (f"Linked from {bpy.path.basename(obj.library.filepath)}, which keeps no result: turn on Store "
                   "Result there, or make a Library Override here")
    _tell(f"{obj.name}: {cache.error}")


class _PassThrough(Exception):
    """Levels 0: the entry shows its input."""


def _swap(helper, old, mesh):
    mesh[stack.RESULT_TAG] = True  # collect() frees it once nothing uses it
    helper.data = mesh
    # A mesh replaced during a render stays (a render job may still read it) until collect() runs after the render,
    # found by its tag: not by name, which the result replacing it takes.
    if old is not None and old != mesh and old.users == 0 and not _rendering:
        bpy.data.meshes.remove(old)
    mesh.name = helper.name


def refresh_all(depsgraph=None, render=False):
    depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
    for obj in [instance.original for instance in depsgraph.objects]:
        refresh(obj, depsgraph, render)


def settings_changed(obj):
    """Property update callback of the entry's settings."""
    if stack.entry(obj) is not None and not _rendering:
        refresh(obj, bpy.context.evaluated_depsgraph_get())


def _dropped():
    for name in [name for name in _caches if stack.entry(bpy.data.objects.get(name)) is None]:
        del _caches[name]  # deleted, renamed or without an entry


def _collect():
    """Frees the helpers, results and node group that no live entry uses any more (stack.collect), and takes pasted
    helpers out of the scene (stack.unlink_helpers); not while a render job may read them."""
    global _busy
    if _busy or _rendering or _saving:
        return
    _busy = True  # the updates removing data makes are not edits
    try:
        stack.collect()
        stack.unlink_helpers()
    finally:
        _busy = False


def _refresh_updated(depsgraph):
    """Refreshes the entries of the objects whose geometry this evaluation changed (edits, settings, animation)."""
    if _busy or _rendering or _saving:
        return
    _dropped()
    updated = {update.id.original for update in depsgraph.updates
               if isinstance(update.id, bpy.types.Object)
               and (update.is_updated_geometry or update.is_updated_transform and _is_cut(update.id.original))}
    changed_settings = _changed_settings()
    updated |= _cut_for_camera(depsgraph) | changed_settings
    # A Base Result is made anew when the object's own mesh or the settings changed: not on the frames of an
    # animation in the modifiers above (a rig's playback).
    changed_meshes = {update.id.original for update in depsgraph.updates if isinstance(update.id, bpy.types.Mesh)}
    for obj in updated:
        stack.tidy(obj)  # a duplicated entry named as one, the helper's fields hidden
        if stack.keep_off_cage(obj):
            _tell(f"{obj.name}: {ON_CAGE_REFUSAL}")
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


def _is_cut(obj):
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
    return {obj for obj in (bpy.data.objects.get(name) for name in _caches) if obj is not None and _is_cut(obj)}


@persistent
def _on_depsgraph_update(scene, depsgraph):
    _attach_when_readable()
    # After edits only (deleting an object or removing an entry is one), not on frame changes: playback deletes nothing.
    _collect()
    _refresh_updated(depsgraph)


@persistent
def _on_frame_change(scene, depsgraph):
    # Playback: the objects whose geometry depends on time are those the new frame updated.
    if depsgraph.mode == 'VIEWPORT':
        _refresh_updated(depsgraph)


@persistent
def _on_render_frame(*_):
    """Before a render evaluates a frame: every entry's result at Render levels, for that frame. Command-line renders
    run this on the main thread. A render from the interface runs it in the render thread, which must not evaluate
    the scene: it asks the main thread and waits."""
    if threading.current_thread() is threading.main_thread():
        _render_levels()
        return
    done = threading.Event()
    _main_thread_work.put((_render_levels, done))
    if not done.wait(_RENDER_WAIT_SECONDS):
        print(f"Loop Subdivision: the interface did not answer within {_RENDER_WAIT_SECONDS} s; "
              "this frame renders the viewport's result")


def _render_levels():
    refresh_all(render=True)


def _viewport_levels():
    refresh_all()
    _collect()


@persistent
def _on_render_start(*_):
    global _rendering
    _rendering = True


@persistent
def _on_render_end(*_):
    # A render wrote its Render levels into the helpers: the viewport gets its levels back once it is over.
    global _rendering
    _rendering = False
    if threading.current_thread() is threading.main_thread():
        _viewport_levels()  # a render from the command line or Python: the render is over, the scene is free
    elif not bpy.app.background:
        _main_thread_work.put((_viewport_levels, None))


# The viewport's adaptive entries follow the view once it has stopped moving: it is read every _WATCH_INTERVAL
# seconds, and an entry is cut again when the view is the one read before (still) and new since the last cut, and its
# rates differ. Cutting while the view moves would stall orbiting on every step.
_WATCH_INTERVAL = 0.25
_watched_view = None
_view_settled = True


def _watch_views():
    # A timer that raises is dropped by Blender: a failure is printed and the watching goes on.
    try:
        _follow_view()
    except Exception:  # any failure: the next view change tries again
        traceback.print_exc()
    return _WATCH_INTERVAL


def _follow_view():
    global _watched_view, _view_settled
    if _busy or _rendering or _saving:
        return
    view = adaptive.viewport_view(bpy.context.window_manager)
    if view != _watched_view:
        _watched_view, _view_settled = view, False
        return
    if _view_settled or view is None:
        return
    _view_settled = True
    depsgraph = None
    for name, cache in list(_caches.items()):
        obj = bpy.data.objects.get(name)
        if cache.cut is None or obj is None or stack.entry(obj) is None:
            continue
        cut_cage, options, matrix_world = cache.cut
        if not _equal(cache.plan_key[-2:], adaptive.rates(cut_cage, options, view, matrix_world)):
            depsgraph = depsgraph or bpy.context.evaluated_depsgraph_get()
            refresh(obj, depsgraph)


# Work that render threads hand to the main thread, which a timer serves while the interface runs.
_main_thread_work = queue.Queue()
_RENDER_WAIT_SECONDS = 60.0
_SERVE_INTERVAL = 0.05


def _serve():
    while not _main_thread_work.empty():
        work, done = _main_thread_work.get()
        try:
            work()
        finally:
            if done is not None:
                done.set()
    return _SERVE_INTERVAL


@persistent
def _on_undo(*_):
    # Undo restores the helpers' meshes as they were: build the next result anew rather than write into one.
    for cache in _caches.values():
        cache.result = cache.inputs = None


@persistent
def _on_load(*_):
    global _attach_pending
    _attach_pending = False
    _caches.clear()
    stack.migrate()
    _undo_auto_smooth_conversion()
    _collect()
    # A file holds no results unless store_result asks (_on_save): every entry's is made anew, as Subdivision
    # Surface's is when a file loads.
    for obj in bpy.data.objects:
        stack.tidy(obj)
    refresh_all()
    _collect()


# The entries whose result _on_save kept out of the file, with their helpers, for _on_saved to put back; and those
# it wrote at Render levels.
_unsaved = []
_stored = []
# From _on_save to _on_saved: the interface draws the file's thumbnail in between, which evaluates the scene (and shows
# the cages); the handlers must not give the entries their results back before the file is written.
_saving = False


@persistent
def _on_save(*_):
    """Nothing of a deleted object, removed entry or finished render goes into the file; nor, by default, the
    results themselves, which can be far larger than the cage (69 times at level 3): each entry points at the
    placeholder meanwhile (stack.placeholder), so that its helper and result have no user and are not written. An
    entry with store_result keeps its result, made at Render levels for the file (machines without the add-on, such
    as render farms, show and render it)."""
    global _busy, _saving
    _collect()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    in_view_layer = {instance.original.name_full for instance in depsgraph.objects}
    empty = None
    for obj, modifier in _local_entries():
        # No file needs a Base Result: a Blender without the add-on has none to show, one with it makes it again.
        base = stack.helper_of(obj, modifier, create=False, socket=stack.BASE_SOCKET)
        if base is not None:
            empty = empty or stack.placeholder()
            _keep_out_of_file(obj, modifier, stack.BASE_SOCKET, base, None, empty)
        if obj.loop_subdivision.store_result:
            if obj.name_full in in_view_layer:
                refresh(obj, depsgraph, render=True)
                _stored.append(obj.name)
            continue
        empty = empty or stack.placeholder()
        _keep_out_of_file(obj, modifier, stack.RESULT_SOCKET, stack.helper_of(obj, modifier, create=False), empty,
                          empty)
    if any(socket == stack.RESULT_SOCKET for _, socket, _, _ in _unsaved):
        compat.show_result_field(stack.node_group(), stack.RESULT_SOCKET, True)
    _saving = True


def _keep_out_of_file(obj, modifier, socket, helper, stand_in, empty):
    """Points the entry's socket at stand_in (the placeholder, or None) until _on_saved, and its helper, if any, at
    the placeholder's (empty) mesh: the helper, with no user, is not written, nor its mesh."""
    global _busy
    _unsaved.append((obj.name, socket, helper.name if helper is not None else None,
                     helper.data.name if helper is not None else None))
    _busy = True
    try:
        compat.set_modifier_input(modifier, socket, stand_in)
        if helper is not None:
            helper.data = empty.data
    finally:
        _busy = False


@persistent
def _on_saved(*_):
    """After saving (or failing to): the entries get their results back as they were before _on_save."""
    global _busy, _saving
    _saving = False
    _busy = True
    try:
        for name, socket, helper_name, result_name in _unsaved:
            obj = bpy.data.objects.get(name)
            modifier = stack.entry(obj)
            helper = bpy.data.objects.get(helper_name) if helper_name is not None else None
            result = bpy.data.meshes.get(result_name) if result_name is not None else None
            if helper is not None and result is not None:
                helper.data = result
            if modifier is not None and helper is not None:
                compat.set_modifier_input(modifier, socket, helper)
        if any(socket == stack.RESULT_SOCKET for _, socket, _, _ in _unsaved):
            compat.show_result_field(stack.node_group(), stack.RESULT_SOCKET, False)
    finally:
        _busy = False
    _unsaved.clear()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for name in _stored:
        obj = bpy.data.objects.get(name)
        if obj is not None:
            refresh(obj, depsgraph)
    _stored.clear()
    _collect()


def _local_entries():
    """The objects of this file with a live entry, and their entries: a list made before any is changed (_drop_base
    removes objects)."""
    return [(obj, modifier) for obj, modifier in ((obj, stack.entry(obj)) for obj in bpy.data.objects)
            if modifier is not None and obj.library is None and obj.users]


def _drop_base(obj, modifier):
    """Takes the entry's Base Result away with its helper and mesh (cache.base is made again on the next refresh).
    Returns whether it had one."""
    global _busy
    helper = stack.helper_of(obj, modifier, create=False, socket=stack.BASE_SOCKET)
    cache = _caches.get(obj.name)
    if cache is not None:
        cache.base = None
    if helper is None:
        return False
    _busy = True
    try:
        compat.set_modifier_input(modifier, stack.BASE_SOCKET, None)
        mesh = helper.data
        bpy.data.objects.remove(helper)
        if mesh is not None and mesh.users == 0:
            bpy.data.meshes.remove(mesh)
    finally:
        _busy = False
    return True


def _undo_auto_smooth_conversion():
    """A file saved before 4.1 and opened in 4.1+ gets "Auto Smooth" modifiers for the meshes that had Auto Smooth on
    (compat.auto_smooth_modifiers); this takes back those that change what 3.x showed:

    - on a helper (hidden from the artist, its result is the entry's alone): always;
    - on an owner, after its entry, when the entry uses the limit surface: its result carries the limit normals as
      custom normals, and 3.x's Auto Smooth did not split a mesh with custom normals (Blender's conversion skips
      objects whose modifiers make custom normals for that reason), while the modifier would split the result's
      fans at its angle and turn the limit normals (39 degrees on a cube at level 1). With Use Limit Surface off
      the result has Blender's own normals, which 3.x split at the cage's angle: that modifier stays and keeps
      doing so."""
    if not compat.converted_auto_smooth():
        return
    for obj in bpy.data.objects:
        modifier = stack.entry(obj)
        if modifier is None or obj.library is not None:
            continue
        helper = stack.helper_of(obj, modifier, create=False)
        if helper is not None and helper.library is None:
            for converted in compat.auto_smooth_modifiers(helper):
                helper.modifiers.remove(converted)
        if obj.loop_subdivision.use_limit_surface:
            index = list(obj.modifiers).index(modifier)
            for converted in compat.auto_smooth_modifiers(obj):
                if list(obj.modifiers).index(converted) > index:
                    obj.modifiers.remove(converted)


_handlers = (
    ("depsgraph_update_post", _on_depsgraph_update),
    ("frame_change_post", _on_frame_change),
    ("render_pre", _on_render_frame),
    ("render_init", _on_render_start),
    # The end of the whole render (an animation renders many frames), not render_post after each frame: the
    # viewport gets its levels back once the render job no longer holds the scene.
    ("render_complete", _on_render_end),
    ("render_cancel", _on_render_end),
    ("undo_post", _on_undo),
    ("redo_post", _on_undo),
    ("load_post", _on_load),
    ("save_pre", _on_save),
    ("save_post", _on_saved),
) + tuple((name, _on_saved) for name in compat.SAVE_FAILED_HANDLERS)


def _detach():
    """The session's entries as a Blender without the add-on shows them, for when the add-on is turned off: each
    entry without Store Result points at the placeholder (its panel's Result field says "Add-on off")
    and shows its input, and its helper and result go. Left live, a result would stay frozen while the cage is
    edited, and a save would write it whole (19 times the cage at level 3)."""
    empty = None
    for obj, modifier in _local_entries():
        _drop_base(obj, modifier)
        if obj.loop_subdivision.store_result:
            continue
        empty = empty or stack.placeholder()
        compat.set_modifier_input(modifier, stack.RESULT_SOCKET, empty)
    if empty is not None:
        compat.show_result_field(stack.node_group(), stack.RESULT_SOCKET, True)
    stack.collect()


def _attach():
    """The session's entries made live again, for when the add-on is turned on in a session that has some (turned
    off before, or entries of a file opened meanwhile, which may want migrating): what opening the file does
    (_on_load), and the placeholder's field hidden again."""
    if not any(stack.entry(obj) is not None for obj in bpy.data.objects):
        return
    _on_load()
    compat.show_result_field(stack.node_group(), stack.RESULT_SOCKET, False)


# Whether the entries wait for _attach: the add-on was turned on while Blender kept its data from add-ons.
_attach_pending = False


def _attach_when_readable():
    """_attach, at the first chance after registering: the next pass of the interface's event loop (a timer), the
    next update of a script's scene (_on_depsgraph_update), or a file's loading, which makes the entries live
    itself (_on_load)."""
    global _attach_pending
    if _attach_pending and _data_readable():
        _attach_pending = False
        _attach()


def register():
    global _attach_pending
    for name, handler in _handlers:
        getattr(bpy.app.handlers, name).append(handler)
    if not bpy.app.background:
        bpy.app.timers.register(_serve, persistent=True)
        bpy.app.timers.register(_watch_views, persistent=True)
    # Blender keeps its data from an add-on while it registers (Preferences, addon_utils.enable, an update, Reload
    # Scripts) and while it starts (then the file's loading makes the results).
    _attach_pending = True
    if not bpy.app.background:
        bpy.app.timers.register(_attach_when_readable, first_interval=0.0)
    _attach_when_readable()


def unregister():
    for name, handler in _handlers:
        getattr(bpy.app.handlers, name).remove(handler)
    for timer in (_serve, _watch_views):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    if bpy.app.timers.is_registered(_attach_when_readable):
        bpy.app.timers.unregister(_attach_when_readable)
    _caches.clear()
    if _data_readable():
        _detach()


def _data_readable():
    """Whether a file's data can be read: not while Blender starts, where add-ons register with bpy.data restricted."""
    return isinstance(bpy.data, bpy.types.BlendData)
