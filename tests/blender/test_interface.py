"""The Loop Subdivision modifier as its panel and keys present it: the Geometry Nodes modifier's own fields hidden
where the Blender version lets an add-on hide them, notes in the singular for one and wrapped at the panel's width,
a duplicated entry named and working as one, and Ctrl 0-5 setting a Loop entry's levels (Blender's Subdivision Set
for objects without one).

Panels are never drawn in background mode or in the bpy module: the hidden fields are checked on the data Blender's
modifier panel reads (NodesModifier flags, the group input's interface flags), and the wrapping by calling the
add-on's own panel draw with a layout that records the labels it is given (the draw code and the data are the real
ones; only the layout is a recorder).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
stack, compat, ui = addon.blender.stack, support.blender_access(addon), addon.ui.panel
live, cage = addon.live.engine, addon.subdivision.cage
check = support.Check("test_interface")


def add_entry(obj, **arguments):
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(**arguments)
    return stack.entry(obj)


def faces_shown(obj):
    return len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)


def edited(obj):
    """An edit of obj's mesh (what runs the add-on's depsgraph handler on it)."""
    obj.data.vertices[0].co.x += 0.01
    obj.data.update()
    bpy.context.evaluated_depsgraph_get().update()


# --- 1. the Geometry Nodes fields -------------------------------------------------------------------------------------

def expected_shown():
    """What each installed version still shows above the settings (compat.hide_geometry_nodes_fields)."""
    if bpy.app.version < (4, 0, 0):
        return ["node group", "Result", "Base Result", "Output Attributes", "Internal Dependencies"]
    if bpy.app.version < (5, 0, 0):
        return ["Manage"]
    return []


def geometry_nodes_fields():
    obj = support.object_from_bmesh("Fields", support.cube("Fields"))
    modifier = add_entry(obj, levels=1)
    socket = (modifier.node_group.interface.items_tree[stack.RESULT_SOCKET]
              if hasattr(modifier.node_group, "interface") else None)
    hidden = []
    if hasattr(modifier, "show_group_selector"):
        hidden.append(("node group picker", not modifier.show_group_selector))
    if socket is not None and hasattr(socket, "hide_in_modifier"):
        hidden.append(("Result field", socket.hide_in_modifier))
    if hasattr(modifier, "show_manage_panel"):
        hidden.append(("Manage panel", not modifier.show_manage_panel))
    # "Output Attributes" has no flag: 4.x and 5.x draw it only for outputs that take an attribute name (none here).
    flags = ([] if bpy.app.version < (4, 0, 0) else ["node group picker", "Result field"]
             + (["Manage panel"] if bpy.app.version >= (5, 0, 0) else []))
    check(all(done for _, done in hidden) and [name for name, _ in hidden] == flags,
          f"a new entry hides what this version lets it hide: {[name for name, _ in hidden]}")
    shown = compat.hide_geometry_nodes_fields(modifier, stack.SOCKETS)
    check(shown == expected_shown(),
          f"Blender {bpy.app.version_string}: what the modifier panel still shows above the settings: {shown}")
    check(faces_shown(obj) == 4 * 12 and compat.modifier_input(modifier, stack.RESULT_SOCKET) is not None,
          "with the Result field hidden the entry still reads its helper: the subdivision shows")
    if hidden:
        # An entry of a file saved before the fields were hidden gets them hidden on its next update.
        if hasattr(modifier, "show_group_selector"):
            modifier.show_group_selector = True
        if socket is not None and hasattr(socket, "hide_in_modifier"):
            socket.hide_in_modifier = False
        if hasattr(modifier, "show_manage_panel"):
            modifier.show_manage_panel = True
        edited(obj)  # the flags are read before anything else of the add-on's runs
        check((not hasattr(modifier, "show_group_selector") or not modifier.show_group_selector)
              and (socket is None or socket.hide_in_modifier)
              and (not hasattr(modifier, "show_manage_panel") or not modifier.show_manage_panel),
              "an entry that showed the fields (an older file's) has them hidden after its next update")
    support.remove(obj)


# --- 3. a duplicated entry ------------------------------------------------------------------------------------------

def duplicated():
    obj = support.object_from_bmesh("Duplicated", support.cube("Duplicated"))
    modifier = add_entry(obj, levels=1)
    with bpy.context.temp_override(object=obj, active_object=obj):
        result = bpy.ops.object.modifier_copy(modifier=modifier.name)
    bpy.context.evaluated_depsgraph_get().update()
    names = [other.name for other in obj.modifiers]
    check(result == {'FINISHED'} and names == ["Loop Subdivision", "Loop Subdivision.001"]
          and stack.is_entry(obj.modifiers[1]),
          f"the modifier's menu ▸ Duplicate gives a Loop Subdivision entry named as one ({names})")
    obj.modifiers.remove(obj.modifiers[0])
    duplicate = stack.entry(obj)
    obj.loop_subdivision.levels = 2
    check(duplicate is not None and duplicate.name == "Loop Subdivision.001" and faces_shown(obj) == 16 * 12,
          f"with the original removed the duplicate is the object's entry and follows its levels "
          f"({faces_shown(obj)} faces at level 2)")
    support.remove(obj)


# --- 2. notes: plurals and wrapping ---------------------------------------------------------------------------------

def notes_of(obj):
    cache = live.cache_of(obj)
    return [text for _, text in cache.messages] if cache is not None else []


def plurals():
    for loose, expected in ((1, "1 loose edge (in no face) is not carried over"),
                            (2, "2 loose edges (in no face) are not carried over")):
        bm = support.cube("Loose")
        for index in range(loose):
            bm.edges.new((bm.verts.new((3 + index, 0, 0)), bm.verts.new((3 + index, 1, 0))))
        obj = support.object_from_bmesh("Loose", bm)
        add_entry(obj)
        notes = notes_of(obj)
        check(any(expected in note for note in notes), f"{loose} loose: the panel says \"{expected}\" ({notes})")
        support.remove(obj)
    bm = support.cube("Crack")
    bm.verts.ensure_lookup_table()
    corner = bm.verts[0].co.copy()  # a triangle with one vertex where a corner of the cube is: one crack
    bm.faces.new((bm.verts.new(corner), bm.verts.new((3, 0, 0)), bm.verts.new((3, 1, 0))))
    obj = support.object_from_bmesh("Crack", bm)
    cracks = addon.model.geometry.shared_positions(support.positions(obj.data))
    add_entry(obj)
    notes = notes_of(obj)
    expected = (f"{cracks} vertex shares a position" if cracks == 1 else f"{cracks} vertices share a position")
    check(cracks >= 1 and any(expected in note for note in notes), f"split vertices: \"{expected}\" ({notes})")
    support.remove(obj)
    bm = support.cube("Flipped")
    bm.faces.ensure_lookup_table()
    bm.faces[0].normal_flip()  # a quad wound against its neighbours: its four edges run the same way as theirs
    obj = support.object_from_bmesh("Flipped", bm)
    add_entry(obj)
    notes = notes_of(obj)
    check(any("4 edges join faces that face opposite ways and stay sharp" in note for note in notes),
          f"a flipped face: the panel names its sharp edges and the way to turn it ({notes})")
    support.remove(obj)
    check(cage.counted(1, "vertex", "vertices") == "1 vertex" and cage.counted(2, "loose edge") ==
          "2 loose edges" and cage.counted(0, "face") == "0 faces", "counted: the singular for one only")


class Region:
    def __init__(self, width):
        self.width = width


class Context:
    def __init__(self, width):
        self.region = Region(width)
        self.preferences = bpy.context.preferences


def wrapping():
    obj = support.object_from_bmesh("Wrapped", support.cube("Wrapped"))
    modifier = add_entry(obj, levels=1)
    obj.loop_subdivision.cone_group = "a vertex group of a very long name that no object of this file has at all"
    error = live.cache_of(obj).error
    for width in (300, 600):
        labels = []
        ui.DATA_PT_loop_subdivision.draw(support.PanelStandIn(modifier, labels), Context(width))
        columns = width // 5  # no character of the interface font is narrower than 5 pixels at scale 1
        error_lines = []
        for index, (label, icon) in enumerate(labels):
            if icon == 'ERROR':
                error_lines = [label] + [text for text, follow in labels[index + 1:] if follow == 'BLANK1']
                break
        longest = max(len(label) for label, _ in labels)
        check(error and " ".join(error_lines) == error and len(error_lines) > 1 and longest <= columns,
              f"{width} pixels: the panel draws the error over {len(error_lines)} labels of at most {columns} "
              f"characters (longest {longest}), the whole text")
    support.remove(obj)

    text = ("vertex group weights of the cone group are read from every vertex of the cage and the note that says "
            "so is long")
    lines = ui.note_lines(text, 30)
    check(all(len(line) <= 30 for line in lines) and " ".join(lines) == text and len(lines) > 2,
          f"a long note splits at words into lines of at most 30 characters ({len(lines)} lines)")
    check(ui.note_lines(text, None) == [text], "without a region (nothing drawn) a note stays whole")
    refusal = "Level 5 needs about 21.3 GB; 21.1 GB are free"
    lines = ui.note_lines(refusal, 24)  # "Level 5 needs about 21.3" is 24 characters: the amount apart from its unit
    check(" ".join(lines) == refusal and not any(line[-1].isdigit() or line.startswith("GB") for line in lines),
          f"an amount keeps its unit on its line ({lines})")
    narrow, wide = ui.note_columns(Context(300)), ui.note_columns(Context(900))
    check(narrow is not None and wide is not None and narrow < wide and narrow >= 20,
          f"the characters per line follow the panel's width ({narrow} at 300 pixels, {wide} at 900)")


# --- 5. Ctrl 0-5 ----------------------------------------------------------------------------------------------------

def subdivision_set():
    ours = support.object_from_bmesh("Ours", support.cube("Ours"))
    add_entry(ours, levels=1)
    plain = support.object_from_bmesh("Plain", support.cube("Plain"))
    support.select_only(ours, plain)
    result = bpy.ops.object.loop_subdivision_set(level=3, relative=False)
    subsurf = [modifier for modifier in plain.modifiers if modifier.type == 'SUBSURF']
    check(result == {'FINISHED'} and ours.loop_subdivision.levels == 3
          and not any(modifier.type == 'SUBSURF' for modifier in ours.modifiers)
          and len(subsurf) == 1 and subsurf[0].levels == 3,
          "Ctrl 3: the Loop entry's Levels Viewport is 3 (no Subdivision Surface added to it); the object without "
          "one gets Blender's Subdivision Surface at level 3")
    check(faces_shown(ours) == 64 * 12, f"the entry shows level 3 ({faces_shown(ours)} faces)")
    bpy.ops.object.loop_subdivision_set(level=-1, relative=True)
    check(ours.loop_subdivision.levels == 2 and subsurf[0].levels == 2, "relative -1: both go down a level")
    bpy.ops.object.loop_subdivision_set(level=9, relative=False)
    check(ours.loop_subdivision.levels == 6, "a level past the entry's maximum sets its maximum, 6")
    support.select_only(plain)
    bpy.ops.object.loop_subdivision_set(level=1, relative=False)
    check(subsurf[0].levels == 1 and ours.loop_subdivision.levels == 6,
          "only an object without a Loop entry selected: Blender's Subdivision Set alone")
    support.select_only(ours)
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.object.loop_subdivision_set(level=2, relative=False)
    in_edit_mode = ours.loop_subdivision.levels
    bpy.ops.object.mode_set(mode='OBJECT')
    check(in_edit_mode == 2, "in Edit Mode too, Subdivision Set sets the Loop entry's levels")
    keyconfig = bpy.context.window_manager.keyconfigs.addon
    if keyconfig is not None:  # background mode may have no key configuration for add-ons
        bound = {name for name in ("Object Mode", "Mesh") if name in keyconfig.keymaps and any(
            item.idname == "object.loop_subdivision_set" and item.ctrl and item.type == 'THREE'
            for item in keyconfig.keymaps[name].keymap_items)}
        check(bound == {"Object Mode", "Mesh"}, f"Ctrl 3 is bound in Object Mode and Edit Mode ({sorted(bound)})")
    support.remove(ours)
    support.remove(plain)


support.clear_scene()
geometry_nodes_fields()
duplicated()
plurals()
wrapping()
subdivision_set()
addon.unregister()
check.finish()
