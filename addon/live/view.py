"""The viewport's adaptive entries follow the view once it has stopped moving (changing the view is no update of any
data, so it is polled): it is read every WATCH_INTERVAL seconds, and an entry is cut again when the view is the one
read before (still) and new since the last cut, and its rates differ. Cutting while the view moves would stall
orbiting on every step."""
import traceback

import bpy

from ..subdivision import adaptive
from . import activity, engine

WATCH_INTERVAL = 0.25
_watched_view = None
_view_settled = True


def watch():
    """The timer. A timer that raises is dropped by Blender: a failure is printed and the watching goes on."""
    try:
        _follow()
    except Exception:  # any failure: the next view change tries again
        traceback.print_exc()
    return WATCH_INTERVAL


def _follow():
    global _watched_view, _view_settled
    if not activity.idle():
        return
    view = adaptive.viewport_view(bpy.context.window_manager)
    if view != _watched_view:
        _watched_view, _view_settled = view, False
        return
    if _view_settled or view is None:
        return
    _view_settled = True
    engine.follow_view(view)
