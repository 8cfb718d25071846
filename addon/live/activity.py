"""What the add-on is doing: the one state its handlers ask before they act.

- writing: the add-on itself changes Blender's data (results, helpers, the entries' inputs): the updates this makes
  are not edits, and no refresh starts meanwhile;
- rendering: from a render job's start to its end the job holds the scene: edits, frame changes and the view leave
  the helpers alone (the work a render asks for is served on its request), and no mesh a render may read is freed;
- saving: from save_pre to save_post the entries point at the placeholder (files.py): the interface draws the file's
  thumbnail in between, which evaluates the scene, and the entries must not get their results back before the file
  is written.
"""
import contextlib

_writing = False
_rendering = False
_saving = False


def idle():
    """Whether the add-on follows edits: it writes nothing, no render holds the scene and no file is being written."""
    return not (_writing or _rendering or _saving)


def may_refresh():
    """Whether an entry may be brought up to date now: a render's own refreshes happen while it renders."""
    return not (_writing or _saving)


def rendering():
    return _rendering


@contextlib.contextmanager
def writing():
    """The add-on changes Blender's data within: the updates it makes are not edits (nested uses end with the
    outermost)."""
    global _writing
    outer = not _writing
    _writing = True
    try:
        yield
    finally:
        if outer:
            _writing = False


def set_rendering(on):
    global _rendering
    _rendering = on


def set_saving(on):
    global _saving
    _saving = on


def reset():
    """Nothing going on: the add-on turned off (a render or a save that never ended leaves no flag behind)."""
    global _writing, _rendering, _saving
    _writing = _rendering = _saving = False
