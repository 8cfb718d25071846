"""Renders: every entry's result at Render levels before each frame a render evaluates, the viewport's levels back
once the render job ends. A render from the interface runs its handlers in the render thread, which must not evaluate
the view layer: it hands the work to the main thread, which a timer serves, and waits."""
import queue
import threading

import bpy
from bpy.app.handlers import persistent

from . import activity, engine

# Work that render threads hand to the main thread.
_main_thread_work = queue.Queue()
_RENDER_WAIT_SECONDS = 60.0
SERVE_INTERVAL = 0.05


@persistent
def on_render_frame(*_):
    """Before a render evaluates a frame: every entry's result at Render levels, for that frame. Command-line renders
    run this on the main thread."""
    if threading.current_thread() is threading.main_thread():
        _render_levels()
        return
    done = threading.Event()
    _main_thread_work.put((_render_levels, done))
    if not done.wait(_RENDER_WAIT_SECONDS):
        print(f"Loop Subdivision: the interface did not answer within {_RENDER_WAIT_SECONDS} s; "
              "this frame renders the viewport's result")


def _render_levels():
    engine.refresh_all(render=True)


def _viewport_levels():
    engine.refresh_all()
    engine.collect()


@persistent
def on_render_start(*_):
    activity.set_rendering(True)


@persistent
def on_render_end(*_):
    # A render wrote its Render levels into the helpers: the viewport gets its levels back once it is over.
    activity.set_rendering(False)
    if threading.current_thread() is threading.main_thread():
        _viewport_levels()  # a render from the command line or Python: the render is over, the scene is free
    elif not bpy.app.background:
        _main_thread_work.put((_viewport_levels, None))


def serve():
    """The timer that does the render threads' work on the main thread."""
    while not _main_thread_work.empty():
        work, done = _main_thread_work.get()
        try:
            work()
        finally:
            if done is not None:
                done.set()
    return SERVE_INTERVAL
