"""Loop Subdivision: Loop subdivision of triangle meshes with creases, through the loopsub native core.

A "Loop Subdivision" modifier in the modifier stack (a Geometry Nodes modifier whose result the add-on keeps
current), an apply operator, and crease tags written as attributes. See docs/addon.md.
"""
import sys

import bpy

# Blender imports an add-on's package again when its files changed (an update from a zip) and on Reload Scripts, but
# not the package's modules, which would keep running the old code: they are imported anew with it (the package's
# names for them go too, or the imports below would take them).
for _name in [name for name in sys.modules if name.startswith(__name__ + ".")]:
    del sys.modules[_name]
    globals().pop(_name.rpartition(".")[2], None)

from . import native  # noqa: E402
from .live import handlers  # noqa: E402
from .ui import operators, panel, properties  # noqa: E402

bl_info = {
    "name": "Loop Subdivision",
    "author": "loopsub team",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties ▸ Modifiers ▸ Add Loop Subdivision; 3D Viewport ▸ Object ▸ Loop Subdivision",
    "description": "Loop subdivision of triangle meshes with creases (Hoppe 94 and OpenSubdiv rules)",
    "category": "Mesh",
}

_modules = (properties, operators, panel, handlers)


def register():
    native.private_folder = bpy.app.tempdir
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
