"""What the artist is told of an entry that cannot work: the status bar for a while (the interface) and the console
(renders and scripts from the command line), beside the panel's note."""
import bpy

_STATUS_SECONDS = 10.0
ON_CAGE_REFUSAL = "Loop Subdivision cannot adjust the edit cage to its result: the cage is drawn as it is"

# The workspaces whose status bar shows what tell said, until clear.
_told = set()


def tell(text):
    """A refusal the artist should see: in the status bar for a while, or until the entry works again, and on the
    console."""
    print(f"Loop Subdivision: {text}")
    if bpy.app.background or bpy.context.window_manager is None:
        return
    _told.update(window.workspace for window in bpy.context.window_manager.windows if window.workspace is not None)
    for workspace in _told:
        workspace.status_text_set(text)
    if bpy.app.timers.is_registered(clear):
        bpy.app.timers.unregister(clear)  # the newest message stays its full while
    bpy.app.timers.register(clear, first_interval=_STATUS_SECONDS)


def clear():
    for workspace in _told:
        try:
            workspace.status_text_set(None)
        except ReferenceError:
            pass  # a workspace deleted meanwhile
    _told.clear()
