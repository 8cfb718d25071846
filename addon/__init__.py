"""Loop Subdivision: Loop subdivision of triangle meshes with creases, through the loopsub native core.

A "Loop Subdivision" modifier in the modifier stack (a Geometry Nodes modifier whose result the add-on keeps
current), an apply operator, and crease tags written as attributes. See docs/addon.md.
"""
from . import live, operators, properties, ui

bl_info = {
    "name": "Loop Subdivision",
    "author": "loopsub team",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties ▸ Modifiers ▸ Add Loop Subdivision; 3D Viewport ▸ Object ▸ Loop Subdivision",
    "description": "Loop subdivision of triangle meshes with creases (Hoppe 94 and OpenSubdiv rules)",
    "category": "Mesh",
}

_modules = (properties, operators, ui, live)


def register():
    for module in _modules:
        module.register()


def unregister():
    for module in reversed(_modules):
        module.unregister()
