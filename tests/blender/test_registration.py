"""Registering and unregistering the add-on twice in one session leaves nothing behind; the extension manifest
parses and has what Blender 4.2 requires; bl_info serves Blender 3.4 to 4.1.
"""
import builtins
import os
import re
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

# The add-on draws nothing itself, so nothing of it may import gpu. The program (blender --background) has not
# imported gpu when the test starts, and then gpu must stay out of sys.modules; Blender as a Python module (PyPI's bpy)
# imports gpu with bpy itself, so there the test watches the imports the add-on's own modules make.
GPU_LOADED_BEFORE = "gpu" in sys.modules
_gpu_importers = []  # the __name__ of every module that imported gpu (or a gpu submodule) since the test started
_import = builtins.__import__


def _watching_import(name, globals=None, locals=None, fromlist=(), level=0):
    if level == 0 and (name == "gpu" or name.startswith("gpu.")):
        _gpu_importers.append((globals or {}).get("__name__", "?"))
    return _import(name, globals, locals, fromlist, level)


builtins.__import__ = _watching_import
addon = support.load_addon(register=False)
check = support.Check("test_registration")

OPERATORS = ("add", "remove", "apply", "refresh_tags", "set")
HANDLERS = ("depsgraph_update_post", "frame_change_post", "render_init", "render_pre", "render_complete",
            "render_cancel", "undo_post",
            "redo_post", "load_post", "save_pre", "save_post")
CLASSES = tuple(f"OBJECT_OT_loop_subdivision_{name}" for name in OPERATORS) + (
    "LoopSubdivisionSettings", "VIEW3D_MT_object_loop_subdivision")
# The part of Blender's modifier panel, registered once per session and kept (ui.DATA_PT_loop_subdivision).
SUB_PANEL = "DATA_PT_loop_subdivision"


def footprint():
    """Everything the add-on may add to a session."""
    return {
        "classes": {name for name in CLASSES
                    if hasattr(bpy.types, name) or bpy.types.PropertyGroup.bl_rna_get_subclass_py(name)},
        "object property": hasattr(bpy.types.Object, "loop_subdivision"),
        "operators": {name for name in OPERATORS if _operator_exists(name)},
        "handlers": {name: len(getattr(bpy.app.handlers, name)) for name in HANDLERS},
        "object menu entries": len(bpy.types.VIEW3D_MT_object._dyn_ui_initialize()),
        "add modifier entries": len(add_modifier_place()._dyn_ui_initialize()),
        "keymap items": keymap_items(),
    }


def keymap_items():
    """The add-on key configuration's items that call the add-on's Subdivision Set, as (keymap, key, ctrl, level)."""
    keyconfig = bpy.context.window_manager.keyconfigs.addon
    if keyconfig is None:
        return []
    return sorted((keymap.name, item.type, bool(item.ctrl), item.properties.level)
                  for keymap in keyconfig.keymaps for item in keymap.keymap_items
                  if item.idname == "object.loop_subdivision_set")


def blender_subdivision_keys():
    """Where the default key configuration binds Blender's own Subdivision Set: Ctrl 0-5, levels 0-5, in Object Mode
    and in Edit Mode ("Mesh") (keymap_data/blender_default.py, _template_items_object_subdivision_set, in 3.4.1 and
    5.2.3). Background mode leaves the default keymaps empty; with an interface they are read."""
    found = sorted((name, item.type, bool(item.ctrl), item.properties.level)
                   for name in ("Object Mode", "Mesh")
                   for item in bpy.context.window_manager.keyconfigs.default.keymaps[name].keymap_items
                   if item.idname == "object.subdivision_set" and not item.properties.relative)
    return found or sorted((name, key, True, level) for name in ("Object Mode", "Mesh")
                           for level, key in enumerate(("ZERO", "ONE", "TWO", "THREE", "FOUR", "FIVE")))


def add_modifier_place():
    """What Properties ▸ Modifiers ▸ Add Modifier is: a button of the panel up to 3.6, a menu from 4.0, whose Generate
    section (where Subdivision Surface is) gets the add-on's entry."""
    return getattr(bpy.types, "OBJECT_MT_modifier_add_generate", None) or bpy.types.DATA_PT_modifiers


def addon_imported_gpu():
    """The add-on's modules that imported gpu, and whether gpu is loaded where the program had not loaded it."""
    own = sorted({name for name in _gpu_importers
                  if name == addon.__name__ or name.startswith(addon.__name__ + ".")})
    return own, not GPU_LOADED_BEFORE and "gpu" in sys.modules


def _operator_exists(name):
    try:
        getattr(bpy.ops.object, f"loop_subdivision_{name}").get_rna_type()
        return True
    except KeyError:
        return False


def registration():
    empty = footprint()
    check(not empty["classes"] and not empty["object property"] and not empty["operators"],
          "nothing of the add-on is there before registering")
    for round_ in (1, 2):
        addon.register()
        full = footprint()
        check(full["classes"] == set(CLASSES) and full["object property"] and full["operators"] == set(OPERATORS),
              f"round {round_}: register adds the classes, Object.loop_subdivision and the operators {full}")
        check(all(full["handlers"][name] == empty["handlers"][name] + 1 for name in HANDLERS)
              and full["object menu entries"] == empty["object menu entries"] + 1
              and full["add modifier entries"] == empty["add modifier entries"] + 1,
              f"round {round_}: one handler of each kind, an Object menu entry and an Add Modifier button")
        for name in OPERATORS:
            rna = getattr(bpy.ops.object, f"loop_subdivision_{name}").get_rna_type()
            check({'REGISTER', 'UNDO'} <= set(bpy.types.Operator.bl_rna_get_subclass_py(
                f"OBJECT_OT_loop_subdivision_{name}").bl_options) and rna.description,
                  f"round {round_}: object.loop_subdivision_{name} has REGISTER, UNDO and a description")
        keys = blender_subdivision_keys()
        check(full["keymap items"] == keys and len(keys) == 12,
              f"round {round_}: Ctrl 0-5 in Object and Edit Mode call the add-on's Subdivision Set, on the keys the "
              f"default key configuration gives Blender's ({full['keymap items']})")
        panel = bpy.types.DATA_PT_loop_subdivision
        check(panel.bl_context == "modifier" and panel.bl_parent_id == "MOD_PT_GeometryNodes",
              "the settings are drawn inside the modifier's own panel in Properties ▸ Modifiers")
        if round_ == 1:
            sub_panel = panel
        check(panel is sub_panel, f"round {round_}: the part of the modifier panel is the one of round 1, never "
                                  "freed under the panels Blender made of it")
        cube = support.object_from_bmesh("Cube", support.cube("Cube"), triangulate=False)  # a note on its quads
        bpy.ops.object.loop_subdivision_add()
        check(addon.blender.stack.entry(cube) is not None, f"round {round_}: the add operator works")
        check(sub_panel_labels(cube), f"round {round_}: the part of the modifier panel draws the entry's settings")
        own, loaded = addon_imported_gpu()
        check(not own and not loaded, f"round {round_}: background mode does not import gpu (modules of the add-on "
              f"that did: {own}; gpu loaded since the start: {loaded})")
        addon.unregister()
        check(hasattr(bpy.types, SUB_PANEL) and not sub_panel_labels(cube),
              f"round {round_}: unregistered, the kept part of the modifier panel draws nothing")
        bpy.data.objects.remove(cube)
        check(footprint() == empty, f"round {round_}: unregister leaves nothing else behind {footprint()}")


def sub_panel_labels(obj):
    """What the registered part of the modifier panel draws for obj's entry (the labels of its notes)."""
    return support.drawn_labels(getattr(bpy.types, SUB_PANEL), obj.modifiers[0])


def fallback_panel():
    """A Blender whose Geometry Nodes modifier panel goes by another name still registers the add-on, with the
    settings in a panel of their own below the stack."""
    panel = addon.ui.panel.DATA_PT_loop_subdivision
    saved = panel.bl_parent_id
    panel.bl_parent_id = "MOD_PT_NoSuchPanel"
    try:
        addon.register()
        check(hasattr(bpy.types, "DATA_PT_loop_subdivision_settings") and not hasattr(bpy.types, SUB_PANEL),
              "without the modifier panel, the settings get a panel of their own")
        addon.unregister()
        check(not hasattr(bpy.types, "DATA_PT_loop_subdivision_settings"), "and unregistering removes it")
    finally:
        panel.bl_parent_id = saved


def manifest():
    path = os.path.join(os.path.dirname(addon.__file__), "blender_manifest.toml")
    with open(path, "rb") as file:
        data = tomllib.load(file)
    required = ("schema_version", "id", "version", "name", "tagline", "maintainer", "type", "blender_version_min",
                "license")
    check(all(key in data for key in required), f"the manifest has Blender 4.2's required fields {required}")
    check(data["schema_version"] == "1.0.0" and data["type"] == "add-on", "schema 1.0.0, type add-on")
    check(re.fullmatch(r"[a-z][a-z0-9_]*", data["id"]) is not None, f"id {data['id']!r} is a valid identifier")
    check(re.fullmatch(r"\d+\.\d+\.\d+", data["version"]) is not None
          and tuple(map(int, data["version"].split("."))) == addon.bl_info["version"],
          "version is semantic and matches bl_info")
    check(len(data["tagline"]) <= 64 and data["tagline"][-1] not in ".!?,;:",
          "tagline at most 64 characters, no closing punctuation")
    check(tuple(map(int, data["blender_version_min"].split("."))) >= (4, 2, 0), "blender_version_min >= 4.2.0")
    check(all(entry.startswith("SPDX:") for entry in data["license"]), "licenses are SPDX identifiers")
    check(set(data.get("platforms", [])) <= {"windows-x64", "windows-arm64", "macos-x64", "macos-arm64", "linux-x64"}
          and data.get("platforms"), "platforms names the built binary's platform")
    info = addon.bl_info
    check(info["blender"] <= bpy.app.version and info["name"] == data["name"],
          f"bl_info loads on Blender {bpy.app.version_string} with the manifest's name")


def without_keymaps():
    """Where there is no window manager (or no add-on key configuration: background mode in some builds) the add-on
    registers without keymap items, and unregisters cleanly."""
    operators = addon.ui.operators
    saved = operators.bpy

    class Context:
        window_manager = None

    class Bpy:
        context = Context()
        utils, types, props, ops, app = saved.utils, saved.types, saved.props, saved.ops, saved.app

    operators.bpy = Bpy()
    try:
        addon.register()
        check(not operators._keymap_items and not keymap_items(),
              "no window manager: the add-on registers, with no keymap items")
        addon.unregister()
    finally:
        operators.bpy = saved
    check(footprint()["operators"] == set(), "and unregisters")


support.clear_scene()
fallback_panel()  # first: the part of the modifier panel, once registered, stays for the session
registration()
without_keymaps()
manifest()
check.finish()
