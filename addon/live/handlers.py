"""The handlers and timers through which Blender drives the add-on, registered and removed together."""
import bpy
from bpy.app.handlers import persistent

from ..blender import interface
from . import activity, engine, files, render, view


@persistent
def on_depsgraph_update(scene, depsgraph):
    files.attach_when_readable()
    # After edits only (deleting an object or removing an entry is one), not on frame changes: playback deletes nothing.
    engine.collect()
    engine.refresh_updated(depsgraph)


@persistent
def on_frame_change(scene, depsgraph):
    # Playback: the objects whose geometry depends on time are those the new frame updated.
    if depsgraph.mode == 'VIEWPORT':
        engine.refresh_updated(depsgraph)


_HANDLERS = (
    ("depsgraph_update_post", on_depsgraph_update),
    ("frame_change_post", on_frame_change),
    ("render_pre", render.on_render_frame),
    ("render_init", render.on_render_start),
    # The end of the whole render (an animation renders many frames), not render_post after each frame: the
    # viewport gets its levels back once the render job no longer holds the scene.
    ("render_complete", render.on_render_end),
    ("render_cancel", render.on_render_end),
    ("undo_post", files.on_undo),
    ("redo_post", files.on_undo),
    ("load_post", files.on_load),
    ("save_pre", files.on_save),
    ("save_post", files.on_saved),
) + tuple((name, files.on_saved) for name in interface.SAVE_FAILED_HANDLERS)

# The interface's timers: the render threads' work served on the main thread, the view followed.
_TIMERS = (render.serve, view.watch)


def register():
    for name, handler in _HANDLERS:
        getattr(bpy.app.handlers, name).append(handler)
    if not bpy.app.background:
        for timer in _TIMERS:
            bpy.app.timers.register(timer, persistent=True)
    files.attach_later()


def unregister():
    for name, handler in _HANDLERS:
        getattr(bpy.app.handlers, name).remove(handler)
    for timer in (*_TIMERS, files.attach_when_readable):
        if bpy.app.timers.is_registered(timer):
            bpy.app.timers.unregister(timer)
    activity.reset()
    files.detach()
