"""Files: what a save writes and what a load, an undo or the add-on turned on or off does to the entries.

A file holds the cage and the settings, not the results (unless Store Result asks), which are made again on loading:
while a file is written every entry without Store Result points at an empty placeholder, so that its helper and
result have no user and are not written, and gets them back after. The add-on turned off leaves the entries as a
Blender without it shows them; turned on, it makes them live again (attach).
"""
import bpy
from bpy.app.handlers import persistent

from ..blender import node_group, shading, stack
from . import activity, engine

# The entries whose result on_save kept out of the file, with their helpers, for on_saved to put back; and those it
# wrote at Render levels.
_unsaved = []
_stored = []


@persistent
def on_undo(*_):
    engine.forget_results()


@persistent
def on_load(*_):
    global _attach_pending
    _attach_pending = False
    engine.forget_all()
    stack.migrate()
    _undo_auto_smooth_conversion()
    engine.collect()
    # A file holds no results unless store_result asks (on_save): every entry's is made anew, as Subdivision
    # Surface's is when a file loads.
    for obj in bpy.data.objects:
        stack.tidy(obj)
    engine.refresh_all()
    engine.collect()


@persistent
def on_save(*_):
    """Nothing of a deleted object, removed entry or finished render goes into the file; nor, by default, the
    results themselves, which can be far larger than the cage (69 times at level 3): each entry points at the
    placeholder meanwhile (stack.placeholder). An entry with store_result keeps its result, made at Render levels for
    the file (machines without the add-on, such as render farms, show and render it)."""
    engine.collect()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    in_view_layer = {instance.original.name_full for instance in depsgraph.objects}
    empty = None
    for obj, modifier in stack.local_entries():
        # No file needs a Base Result: a Blender without the add-on has none to show, one with it makes it again.
        base = stack.helper_of(obj, modifier, create=False, socket=stack.BASE_SOCKET)
        if base is not None:
            empty = empty or stack.placeholder()
            _keep_out_of_file(obj, modifier, stack.BASE_SOCKET, base, None, empty)
        if obj.loop_subdivision.store_result:
            if obj.name_full in in_view_layer:
                engine.refresh(obj, depsgraph, render=True)
                _stored.append(obj.name)
            continue
        empty = empty or stack.placeholder()
        _keep_out_of_file(obj, modifier, stack.RESULT_SOCKET, stack.helper_of(obj, modifier, create=False), empty,
                          empty)
    if any(socket == stack.RESULT_SOCKET for _, socket, _, _ in _unsaved):
        node_group.show_result_field(True)
    activity.set_saving(True)


def _keep_out_of_file(obj, modifier, socket, helper, stand_in, empty):
    """Points the entry's socket at stand_in (the placeholder, or None) until on_saved, and its helper, if any, at
    the placeholder's (empty) mesh: the helper, with no user, is not written, nor its mesh."""
    _unsaved.append((obj.name, socket, helper.name if helper is not None else None,
                     helper.data.name if helper is not None else None))
    with activity.writing():
        stack.set_modifier_input(modifier, socket, stand_in)
        if helper is not None:
            helper.data = empty.data


@persistent
def on_saved(*_):
    """After saving (or failing to): the entries get their results back as they were before on_save."""
    activity.set_saving(False)
    with activity.writing():
        for name, socket, helper_name, result_name in _unsaved:
            obj = bpy.data.objects.get(name)
            modifier = stack.entry(obj)
            helper = bpy.data.objects.get(helper_name) if helper_name is not None else None
            result = bpy.data.meshes.get(result_name) if result_name is not None else None
            if helper is not None and result is not None:
                helper.data = result
            if modifier is not None and helper is not None:
                stack.set_modifier_input(modifier, socket, helper)
        if any(socket == stack.RESULT_SOCKET for _, socket, _, _ in _unsaved):
            node_group.show_result_field(False)
    _unsaved.clear()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    for name in _stored:
        obj = bpy.data.objects.get(name)
        if obj is not None:
            engine.refresh(obj, depsgraph)
    _stored.clear()
    engine.collect()


def _undo_auto_smooth_conversion():
    """A file saved before 4.1 and opened in 4.1+ gets "Auto Smooth" modifiers for the meshes that had Auto Smooth on
    (shading.auto_smooth_modifiers); this takes back those that change what 3.x showed:

    - on a helper (hidden from the artist, its result is the entry's alone): always;
    - on an owner, after its entry, when the entry uses the limit surface: its result carries the limit normals as
      custom normals, and 3.x's Auto Smooth did not split a mesh with custom normals (Blender's conversion skips
      objects whose modifiers make custom normals for that reason), while the modifier would split the result's
      fans at its angle and turn the limit normals (39 degrees on a cube at level 1). With Use Limit Surface off
      the result has Blender's own normals, which 3.x split at the cage's angle: that modifier stays and keeps
      doing so."""
    if not shading.converted_auto_smooth():
        return
    for obj in bpy.data.objects:
        modifier = stack.entry(obj)
        if modifier is None or obj.library is not None:
            continue
        helper = stack.helper_of(obj, modifier, create=False)
        if helper is not None and helper.library is None:
            for converted in shading.auto_smooth_modifiers(helper):
                helper.modifiers.remove(converted)
        if obj.loop_subdivision.use_limit_surface:
            index = list(obj.modifiers).index(modifier)
            for converted in shading.auto_smooth_modifiers(obj):
                if list(obj.modifiers).index(converted) > index:
                    obj.modifiers.remove(converted)


def detach():
    """The session's entries as a Blender without the add-on shows them, for when the add-on is turned off: each
    entry without Store Result points at the placeholder (its panel's Result field says "Add-on off")
    and shows its input, and its helper and result go. Left live, a result would stay frozen while the cage is
    edited, and a save would write it whole (19 times the cage at level 3)."""
    engine.forget_all()
    if not _data_readable():
        return
    empty = None
    for obj, modifier in stack.local_entries():
        with activity.writing():
            stack.drop_base(obj, modifier)
        if obj.loop_subdivision.store_result:
            continue
        empty = empty or stack.placeholder()
        stack.set_modifier_input(modifier, stack.RESULT_SOCKET, empty)
    if empty is not None:
        node_group.show_result_field(True)
    stack.collect()


# Whether the entries wait for attach: the add-on was turned on while Blender kept its data from add-ons.
_attach_pending = False


def attach_later():
    """attach at the first chance: Blender keeps its data from an add-on while it registers (Preferences,
    addon_utils.enable, an update, Reload Scripts) and while it starts (then the file's loading makes the results)."""
    global _attach_pending
    _attach_pending = True
    if not bpy.app.background:
        bpy.app.timers.register(attach_when_readable, first_interval=0.0)
    attach_when_readable()


def attach_when_readable():
    """The session's entries made live again, for when the add-on is turned on in a session that has some (turned
    off before, or entries of a file opened meanwhile, which may want migrating): what opening the file does
    (on_load), and the placeholder's field hidden again; at the first chance after registering: the next pass of the
    interface's event loop (a timer), the next update of a script's scene, or a file's loading, which makes the
    entries live itself."""
    global _attach_pending
    if not _attach_pending or not _data_readable():
        return
    _attach_pending = False
    if any(stack.entry(obj) is not None for obj in bpy.data.objects):
        on_load()
        node_group.show_result_field(False)


def _data_readable():
    """Whether a file's data can be read: not while Blender starts, where add-ons register with bpy.data restricted."""
    return isinstance(bpy.data, bpy.types.BlendData)
