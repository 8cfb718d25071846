"""Where the interface differs between versions: the Add Modifier button (3.x draws it in the panel
DATA_PT_modifiers, 4.0+ has a menu with a Generate section), the modifier panel a sub-panel goes into, the arguments
of object.subdivision_set, and the handlers Blender runs when writing a file failed.
"""
import bpy

def add_modifier_button(draw):
    """Puts draw(self, context) under Properties ▸ Modifiers ▸ Add Modifier: 3.x draws that button in the panel
    DATA_PT_modifiers, 4.0+ has a menu with a Generate section. Returns what remove_modifier_button needs."""
    menu = getattr(bpy.types, "OBJECT_MT_modifier_add_generate", None)
    target = menu if menu is not None else bpy.types.DATA_PT_modifiers
    target.append(draw)
    return target


def remove_modifier_button(target, draw):
    target.remove(draw)


# Blender draws each modifier in an instanced panel of this type; a Python sub-panel of it is drawn inside every
# Geometry Nodes modifier's panel, with that modifier as the panel's custom_data.
NODES_MODIFIER_PANEL = "MOD_PT_GeometryNodes"


# Handlers Blender runs when writing a file failed, where it has them: as after saving, the results go back.
SAVE_FAILED_HANDLERS = tuple(name for name in ("save_post_fail",) if hasattr(bpy.app.handlers, name))


def subdivision_set_arguments(**arguments):
    """The arguments Blender's object.subdivision_set (Ctrl 0-5) takes, of those given: level and relative in every
    version, ensure_modifier (hidden: add a Subdivision Surface where there is none) from 4.5 (4.5.15 and later here;
    3.4.1 and 4.2.23 have no such argument)."""
    known = bpy.ops.object.subdivision_set.get_rna_type().properties.keys()
    return {name: value for name, value in arguments.items() if name in known}
