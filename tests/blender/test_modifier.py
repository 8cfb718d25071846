"""The Loop Subdivision modifier as an artist and a pipeline meet it: an entry of the modifier stack that modifiers
above feed and modifiers below act on, Levels Viewport and Render levels, edits in Object and Edit Mode re-using the
plan, animation frame by frame, renders (`blender -b file -f N` in a second process), Blender's own Apply, files
opened where the add-on is missing, copied objects, errors shown without losing the input, and no update loops.

What the entry shows is checked against what the apply operator writes for the same input (apply is checked against
Blender's Subdivision Surface and OpenSubdiv by the other tests), and against Blender's own modifiers' arithmetic.
"""
import os
import sys
import tempfile
import weakref

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402
from mathutils import Vector  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_modifier")
ADDON_DIR = os.path.dirname(addon.__file__)
stack = addon.blender.stack


def evaluated(obj, entry_shown=True):
    """The object's evaluated mesh as (positions, number of faces); with entry_shown=False, its input (the entry
    hidden in the viewport for the evaluation)."""
    modifier = stack.entry(obj)
    if not entry_shown:
        modifier.show_viewport = False
    try:
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        return support.positions(mesh), len(mesh.polygons)
    finally:
        if modifier is not None:
            modifier.show_viewport = True


def applied(obj, **arguments):
    """What the apply operator writes for obj's own mesh, on a copy (positions, faces)."""
    twin = support.copy_object(obj, obj.name + " twin")
    twin.modifiers.clear()
    support.apply_loop(twin, **arguments)
    result = support.positions(twin.data), len(twin.data.polygons)
    support.remove(twin)
    support.select_only(obj)
    return result


def add_entry(obj, **arguments):
    support.select_only(obj)
    result = bpy.ops.object.loop_subdivision_add(**arguments)
    return result, obj.modifiers[-1]


def plan_builds(obj):
    return addon.live.engine.cache_of(obj).plan_builds


# --- in the stack ---------------------------------------------------------------------------------------------------

def entry_in_stack():
    obj = support.object_from_bmesh("Sphere", support.uv_sphere(8, 6))
    cage_faces = len(obj.data.polygons)
    result, modifier = add_entry(obj)
    check(result == {'FINISHED'} and modifier.name.startswith("Loop Subdivision") and modifier.type == 'NODES',
          "the add operator puts a modifier named Loop Subdivision at the end of the stack")
    check(modifier.show_in_editmode and not modifier.show_on_cage, "it shows in Edit Mode, on the cage off")
    with bpy.context.temp_override(object=obj, active_object=obj):
        bpy.ops.object.mode_set(mode='EDIT')
        modifier.show_on_cage = True  # what the header's toggle sets
        _, printed = support.capture_output(lambda: bpy.context.evaluated_depsgraph_get().update())
        bpy.ops.object.mode_set(mode='OBJECT')
    check(not modifier.show_on_cage and addon.live.status.ON_CAGE_REFUSAL in printed,
          "On Cage turned on in Edit Mode turns off again, the cage drawn as it is, and the add-on says why")
    positions, faces = evaluated(obj)
    check(faces == 4 * cage_faces, f"the evaluated mesh has Levels Viewport (1): {faces} faces")
    expected, _ = applied(obj, levels=1)
    check(np.array_equal(positions, expected), "the entry shows exactly what Apply writes")
    check(bpy.ops.object.loop_subdivision_add.poll() is False, "one entry per object: adding again is refused")

    obj.loop_subdivision.levels = 2
    positions, faces = evaluated(obj)
    check(faces == 16 * cage_faces, "changing Levels Viewport changes the result")
    obj.loop_subdivision.levels = 0
    check(evaluated(obj)[1] == cage_faces, "Levels Viewport 0 shows the input")
    obj.loop_subdivision.levels = 1
    support.remove(obj)


def stack_order():
    grid = support.object_from_bmesh("Grid", support.grid(3))
    triangles = len(grid.data.polygons)
    boundary = int(np.count_nonzero(support.edge_face_counts(grid.data) == 1))
    solidify = grid.modifiers.new("Solidify", 'SOLIDIFY')
    solidify.thickness = 0.2
    add_entry(grid, levels=1)
    _, faces = evaluated(grid)
    check(faces == 4 * (2 * triangles + 2 * boundary),
          f"a Solidify above feeds the entry: the shell and its rim (triangulated) are subdivided ({faces} faces)")
    bpy.ops.object.modifier_move_to_index(modifier=grid.modifiers[-1].name, index=0)
    _, faces = evaluated(grid)
    check(faces == 2 * 4 * triangles + 2 * boundary,
          f"moved above it, the Solidify acts on the result: its rim has one quad per child edge ({faces} faces)")
    support.remove(grid)

    obj = support.object_from_bmesh("Mirrored", support.uv_sphere(8, 6))
    for vertex in obj.data.vertices:
        vertex.co.x += 2.0
    mirror = obj.modifiers.new("Mirror", 'MIRROR')
    mirror.use_mirror_merge = False
    _, modifier = add_entry(obj)
    positions, faces = evaluated(obj)
    alone, alone_faces = applied(obj, levels=1)
    check(faces == 2 * alone_faces, "a Mirror above doubles the faces the entry subdivides")
    right = positions[positions[:, 0] > 0]
    left = positions[positions[:, 0] < 0] * np.array([-1.0, 1.0, 1.0], dtype=np.float32)
    check(len(right) == len(left) == len(alone)
          and np.abs(np.sort(right, axis=0) - np.sort(alone, axis=0)).max() < 1e-6
          and np.abs(np.sort(left, axis=0) - np.sort(alone, axis=0)).max() < 1e-6,
          "each mirrored half is the subdivision of the cage (a Mirror commutes with Loop)")

    displace = obj.modifiers.new("Displace", 'DISPLACE')
    displace.direction = 'Z'
    displace.strength = 0.5
    moved, moved_faces = evaluated(obj)
    check(moved_faces == faces and np.abs(moved - positions - [0, 0, 0.25]).max() < 1e-6,
          "a Displace below moves the result by its strength x (1 - midlevel)")
    displace.show_viewport = False
    check(np.array_equal(evaluated(obj)[0], positions), "switching the Displace off gives the result back")
    modifier.show_viewport = False
    _, faces = evaluated(obj)
    check(faces == 2 * len(obj.data.polygons), "switching the entry off in the viewport shows its input")
    modifier.show_viewport = True
    support.remove(obj)


# --- edits, animation -----------------------------------------------------------------------------------------------

def edits():
    obj = support.object_from_bmesh("Edited", support.uv_sphere(8, 6))
    add_entry(obj)
    builds = plan_builds(obj)
    before, _ = evaluated(obj)
    obj.data.vertices[0].co.z += 0.25
    obj.data.update()
    after, _ = evaluated(obj)
    check(plan_builds(obj) == builds and not np.array_equal(before, after)
          and np.array_equal(after, applied(obj, levels=1)[0]),
          "moving a vertex in Object Mode updates the result with the same plan")

    helper = addon.blender.stack.modifier_input(obj.modifiers[-1], "Result")
    mesh_pointer = helper.data.as_pointer()
    for _ in range(3):
        bpy.context.view_layer.update()
    check(helper.data.as_pointer() == mesh_pointer and np.array_equal(evaluated(obj)[0], after)
          and plan_builds(obj) == builds, "updates that change nothing leave the result alone (no update loop)")

    bpy.ops.object.mode_set(mode='EDIT')
    edit = bmesh.from_edit_mesh(obj.data)
    edit.verts.ensure_lookup_table()
    edit.verts[3].co.x += 0.3
    bmesh.update_edit_mesh(obj.data)
    in_edit, _ = evaluated(obj)
    check(plan_builds(obj) == builds and not np.array_equal(in_edit, after),
          "in Edit Mode a vertex move shows in the result, with the same plan")
    edit.faces.ensure_lookup_table()
    old_plan = weakref.ref(addon.live.engine.cache_of(obj).output.plan)
    old_gone_when_built = []
    build_plan = addon.subdivision.cage.Source.plan

    def watched_build(source, *arguments, **keywords):
        old_gone_when_built.append(old_plan() is None)
        return build_plan(source, *arguments, **keywords)

    addon.subdivision.cage.Source.plan = watched_build
    try:
        bmesh.ops.delete(edit, geom=[edit.faces[0]], context='FACES_ONLY')
        bmesh.update_edit_mesh(obj.data)
        _, faces = evaluated(obj)
    finally:
        addon.subdivision.cage.Source.plan = build_plan
    check(plan_builds(obj) == builds + 1 and faces == 4 * (len(obj.data.polygons) - 1),
          "in Edit Mode deleting a face builds a new plan")
    check(old_gone_when_built == [True],
          "the old plan is let go before the new one is built (a large result's two plans are never held at once)")
    # Rotating an edge keeps every count (vertices, edges, faces) and the layout: only the plan tells the results apart.
    edit.edges.ensure_lookup_table()
    inner = next(edge for edge in edit.edges if len(edge.link_faces) == 2
                 and all(len(face.verts) == 3 for face in edge.link_faces))
    bmesh.ops.rotate_edges(edit, edges=[inner], use_ccw=True)
    bmesh.update_edit_mesh(obj.data)
    bpy.ops.object.mode_set(mode='OBJECT')
    shown = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    shown_corners = support.read_array(shown.loops, "vertex_index", dtype=np.int32)
    twin = support.copy_object(obj, "Edited twin")
    twin.modifiers.clear()
    support.apply_loop(twin, levels=1)
    twin_corners = support.read_array(twin.data.loops, "vertex_index", dtype=np.int32)
    check(plan_builds(obj) == builds + 2 and np.array_equal(shown_corners, twin_corners)
          and np.array_equal(support.positions(shown), support.positions(twin.data)),
          "rotating an edge in Edit Mode gives the subdivision of the new triangles, not the old ones moved")
    support.remove(twin)
    support.select_only(obj)
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.object.mode_set(mode='OBJECT')
    check(np.array_equal(evaluated(obj)[0], applied(obj, levels=1)[0]),
          "back in Object Mode the result is the subdivision of the edited mesh")
    support.remove(obj)


def edit_mode_with_vertex_groups():
    """A cage with a vertex group, edited in Edit Mode: a topology change rebuilds the result there (vertex groups are
    written through Convert Attribute, which refuses while an object is in Edit Mode unless given another)."""
    obj = support.object_from_bmesh("Grouped", support.uv_sphere())
    obj.vertex_groups.new(name="Weights").add(list(range(len(obj.data.vertices))), 0.5, 'REPLACE')
    add_entry(obj, levels=1)
    faces = len(obj.data.polygons)
    bpy.ops.object.mode_set(mode='EDIT')
    edit = bmesh.from_edit_mesh(obj.data)
    edit.faces.ensure_lookup_table()
    bmesh.ops.delete(edit, geom=[edit.faces[0]], context='FACES_ONLY')
    bmesh.update_edit_mesh(obj.data)
    _, shown = evaluated(obj)
    helper = addon.blender.stack.modifier_input(obj.modifiers[-1], "Result")
    weights = {round(group.weight, 6) for vertex in helper.data.vertices for group in vertex.groups}
    check(shown == 4 * (faces - 1) and [group.name for group in helper.vertex_groups] == ["Weights"]
          and weights == {0.5} and all(len(vertex.groups) == 1 for vertex in helper.data.vertices),
          f"in Edit Mode, deleting a face of a cage with a vertex group rebuilds the result ({shown} faces, "
          f"{4 * (faces - 1)} expected) with the group's weights on every vertex")
    bpy.ops.object.mode_set(mode='OBJECT')
    support.remove(obj)


def uv_edits():
    """A moved vertex and a moved UV of a cage with a UV map and a corner colour are written into the result in place,
    UVs, colours and (once the result is still) limit normals included, as Apply would write them, each alone too (an
    update refines only the values that changed); a UV split off its vertex's other corners (a new seam) builds a new
    plan."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    obj = support.object_from_bmesh("UVEdited", bm)
    colors = obj.data.color_attributes.new("Paint", 'FLOAT_COLOR', 'CORNER')
    colors.data.foreach_set("color", np.tile([0.2, 0.4, 0.6, 1.0], len(obj.data.loops)).astype(np.float32))
    add_entry(obj)

    def shown_and_applied():
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        shown = (support.positions(mesh), support.read_array(mesh.uv_layers["UVMap"].data, "uv", 2),
                 support.read_array(mesh.attributes["Paint"].data, "color", 4), corner_normals(mesh))
        twin = support.copy_object(obj, "UVEdited twin")
        twin.modifiers.clear()
        support.apply_loop(twin, levels=1)
        expected = (support.positions(twin.data), support.read_array(twin.data.uv_layers["UVMap"].data, "uv", 2),
                    support.read_array(twin.data.attributes["Paint"].data, "color", 4), corner_normals(twin.data))
        support.remove(twin)
        support.select_only(obj)
        return all(np.array_equal(a, b) for a, b in zip(shown[:3], expected[:3])), \
            float(np.abs(shown[3] - expected[3]).max())

    builds = plan_builds(obj)
    loop_vertices = support.read_array(obj.data.loops, "vertex_index", dtype=np.int32)

    def move_uv(vertex, uv):
        """Every corner of vertex with the UV of its first corner takes uv: the value moves, the UV topology stays."""
        uvs = support.read_array(obj.data.uv_layers["UVMap"].data, "uv", 2)
        first = np.flatnonzero(loop_vertices == vertex)[0]
        uvs[(loop_vertices == vertex) & (uvs == uvs[first]).all(axis=1)] = uv
        obj.data.uv_layers["UVMap"].data.foreach_set("uv", uvs.ravel())

    move_uv(0, (0.9, 0.1))
    obj.data.vertices[0].co.z += 0.25
    obj.data.update()
    same, normals = shown_and_applied()
    check(plan_builds(obj) == builds and same and normals < 1e-6,
          "with a UV map and corner colours, an edit is written in place: positions, UVs, colours and normals as "
          f"Apply's (normals within {normals:.1e})")
    edits_alone = {
        "a vertex": lambda: setattr(obj.data.vertices[1], "co", obj.data.vertices[1].co + Vector((0.1, 0.0, 0.05))),
        "a UV": lambda: move_uv(2, (0.3, 0.7)),
        "a corner colour": lambda: setattr(obj.data.color_attributes["Paint"].data[5], "color", (1.0, 0.0, 0.5, 1.0)),
    }
    for what, edit in edits_alone.items():
        edit()
        obj.data.update()
        same, normals = shown_and_applied()
        check(plan_builds(obj) == builds and same and normals < 1e-6,
              f"{what} edited alone is written in place, the result as Apply's (normals within {normals:.1e})")
    obj.data.uv_layers["UVMap"].data[0].uv = (0.5, 0.5)  # one corner leaves its vertex's others: a new seam
    obj.data.update()
    same, normals = shown_and_applied()
    check(plan_builds(obj) == builds + 1 and same and normals < 1e-6,
          "a UV split off its vertex's other corners builds a new plan, and the result is Apply's")
    support.remove(obj)


def corner_normals(mesh):
    return addon.blender.shading.read_corner_normals(mesh)


def animation():
    scene = bpy.context.scene
    obj = support.object_from_bmesh("Waving", support.grid(6))
    wave = obj.modifiers.new("Wave", 'WAVE')
    wave.height = 0.3
    add_entry(obj)
    results = []
    for frame in (1, 7):
        scene.frame_set(frame)
        results.append(evaluated(obj)[0])
    check(not np.array_equal(results[0], results[1]), "a Wave above: the result follows the frame")
    scene.frame_set(1)
    check(np.array_equal(evaluated(obj)[0], results[0]), "back at frame 1, the frame-1 result again")
    support.remove(obj)

    obj = support.object_from_bmesh("Keyed", support.uv_sphere(8, 6))
    obj.shape_key_add(name="Basis")
    raised = obj.shape_key_add(name="Raised")
    for point in raised.data:
        point.co.z += 0.5
    raised.value = 0.0
    raised.keyframe_insert("value", frame=1)
    raised.value = 1.0
    raised.keyframe_insert("value", frame=11)
    add_entry(obj)
    scene.frame_set(1)
    low, _ = evaluated(obj)
    scene.frame_set(11)
    high, _ = evaluated(obj)
    check(np.abs(high - low - [0.0, 0.0, 0.5]).max() < 1e-5,
          "an animated shape key moves the result with it (a uniform lift stays a uniform lift)")
    scene.frame_set(1)
    support.remove(obj)

    # Levels Viewport keyframed, as Subdivision Surface's Levels can be: each frame shows its level.
    obj = support.object_from_bmesh("Levelled", support.cube("Levelled"))
    add_entry(obj, levels=1)
    settings = obj.loop_subdivision
    for frame, levels in ((1, 1), (11, 3)):
        settings.levels = levels
        settings.keyframe_insert("levels", frame=frame)
    shown = []
    for frame in (1, 11, 1, 11):
        scene.frame_set(frame)
        # Not evaluated(): its show_viewport write would tag the object, and the next frame would update for that.
        shown.append(len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons))
    cage = len(obj.data.polygons)
    check(shown == [4 * cage, 64 * cage, 4 * cage, 64 * cage],
          f"a keyframed Levels Viewport: each frame shows its level ({shown} faces at frames 1, 11, 1, 11)")
    obj.animation_data_clear()
    support.remove(obj)


# --- errors ---------------------------------------------------------------------------------------------------------

def errors():
    obj = support.object_from_bmesh("Broken", support.uv_sphere(8, 6))
    add_entry(obj)
    good, _ = evaluated(obj)
    obj.data.vertices[1].co.x = float("nan")
    told = []
    tell, addon.live.status.tell = addon.live.status.tell, told.append
    try:
        obj.data.update()
        _, faces = evaluated(obj)
    finally:
        addon.live.status.tell = tell
    error = addon.live.engine.cache_of(obj).error
    check(faces == len(obj.data.polygons) and "non-finite" in error,
          f"a bad input passes through unchanged and the panel says why ({error})")
    check(told == [error] and error.startswith("Broken: ") and not error.startswith("Broken: Broken"),
          f"the console and the status bar say it once, naming the object once ({told})")
    obj.data.vertices[1].co.x = 0.0
    obj.data.update()
    _, faces = evaluated(obj)
    check(faces == 4 * len(obj.data.polygons) and not addon.live.engine.cache_of(obj).error,
          "fixed, it subdivides again")
    support.remove(obj)


def undo():
    """Undo in background mode needs a first step and operators called with the positional undo flag, as a click
    would push them (see test_apply.undo_restores)."""
    obj = support.object_from_bmesh("Undone", support.uv_sphere(8, 6))
    cage_faces = len(obj.data.polygons)
    bpy.ops.ed.undo_push(message="before adding")
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add('EXEC_DEFAULT', True, levels=1)
    obj.loop_subdivision.levels = 2
    bpy.ops.ed.undo_push(message="levels 2")
    check(evaluated(obj)[1] == 16 * cage_faces, "levels 2 shows")
    bpy.ops.ed.undo()
    obj = bpy.data.objects["Undone"]
    check(obj.loop_subdivision.levels == 1 and evaluated(obj)[1] == 4 * cage_faces,
          "undo brings back level 1 and its result")
    bpy.ops.ed.undo()
    obj = bpy.data.objects["Undone"]
    check(addon.blender.stack.entry(obj) is None and evaluated(obj)[1] == cage_faces, "undo again removes the entry")
    bpy.ops.ed.redo()
    obj = bpy.data.objects["Undone"]
    check(addon.blender.stack.entry(obj) is not None and evaluated(obj)[1] == 4 * cage_faces,
          "redo brings the entry back with its result")
    obj.data.vertices[0].co.z += 0.2
    obj.data.update()
    check(np.array_equal(evaluated(obj)[0], applied(obj, levels=1)[0]), "and it is live again after undo and redo")
    support.remove(obj)


# --- copies, Apply, files, renders ----------------------------------------------------------------------------------

def copies():
    obj = support.object_from_bmesh("Original", support.uv_sphere(8, 6))
    add_entry(obj)
    linked = obj.copy()  # what Alt D makes: the same mesh, a copy of the object and its modifiers
    linked.name = "Linked"
    bpy.context.scene.collection.objects.link(linked)
    linked.loop_subdivision.levels = 2
    result = addon.blender.stack.modifier_input
    check(result(linked.modifiers[-1], "Result") != result(obj.modifiers[-1], "Result"),
          "a copied object gets a result of its own")
    check(evaluated(linked)[1] == 16 * len(obj.data.polygons) and evaluated(obj)[1] == 4 * len(obj.data.polygons),
          "the copy and the original each show their own levels")
    support.remove(linked)
    support.remove(obj)


def blender_apply():
    obj = support.object_from_bmesh("BlenderApply", support.uv_sphere(8, 6))
    _, modifier = add_entry(obj, levels=2)
    positions, faces = evaluated(obj)
    with bpy.context.temp_override(object=obj, active_object=obj):
        result = bpy.ops.object.modifier_apply(modifier=modifier.name)
    check(result == {'FINISHED'} and not obj.modifiers and len(obj.data.polygons) == faces
          and np.array_equal(support.positions(obj.data), positions),
          "Blender's own Apply writes the result into the mesh and removes the entry")
    support.remove(obj)

    obj = support.object_from_bmesh("OperatorApply", support.uv_sphere(8, 6))
    obj.modifiers.new("Displace", 'DISPLACE')
    add_entry(obj, levels=1)
    result, output = support.capture_output(lambda: bpy.ops.object.loop_subdivision_apply())
    check(result == {'FINISHED'} and "was not first" in output and [m.type for m in obj.modifiers] == ['DISPLACE'],
          "the add-on's Apply on an entry that is not first warns as Blender does, and removes the entry")
    support.remove(obj)


def saved_and_rendered():
    obj = support.shade_smooth(support.object_from_bmesh("Saved", support.uv_sphere(8, 6)))  # the limit normals show
    obj.data.materials.append(bpy.data.materials.new("Paint"))
    obj.modifiers.new("Wave", 'WAVE').height = 0.3
    add_entry(obj, levels=1, render_levels=2)
    cage_positions, cage_faces = evaluated(obj, entry_shown=False)
    obj.loop_subdivision.levels = 2
    render_positions, _ = evaluated(obj)
    obj.loop_subdivision.levels = 1
    positions, faces = evaluated(obj)
    camera = support.tiny_render_camera(6.0)
    without_addon = f"""
import addon_utils, bpy, numpy as np
assert not any(m.__name__.startswith("loop") or m.__name__ == "addon" for m in addon_utils.modules()
               if addon_utils.check(m.__name__)[1])
obj = bpy.data.objects["Saved"]
mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
co = np.empty(len(mesh.vertices) * 3, np.float32); mesh.vertices.foreach_get("co", co)
modifier = obj.modifiers["{stack.ENTRY_NAME}"]
inputs = getattr(getattr(modifier, "properties", None), "inputs", None)
values = ([getattr(getattr(inputs, name), "value", None) for name in dir(inputs) if name.startswith("Socket")]
          if inputs is not None else modifier.values())
np.save(PATH + ".seen.npy", co.reshape(-1, 3))
print("WITHOUT-ADDON", len(mesh.polygons), [m.name for m in mesh.materials if m is not None],
      "RESULT-FIELD", [value.name for value in values if isinstance(value, bpy.types.Object)])
"""
    with tempfile.TemporaryDirectory() as folder:
        for store in (False, True):
            obj.loop_subdivision.store_result = store
            path = os.path.join(folder, f"saved-{store}.blend")
            bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
            code, output = support.run_blender(path, f"PATH = {path!r}\n" + without_addon)
            seen = np.load(path + ".seen.npy") if os.path.exists(path + ".seen.npy") else None
            if store:
                check(f"WITHOUT-ADDON {4 * faces} ['Paint']" in output and np.array_equal(seen, render_positions),
                      "with Store Result, a Blender without the add-on opens the file and shows the result at "
                      "Render levels, materials included")
            else:
                check(f"WITHOUT-ADDON {cage_faces} ['Paint'] RESULT-FIELD ['{stack.PLACEHOLDER_NAME}']" in output
                      and np.array_equal(seen, cage_positions) and len(stack.PLACEHOLDER_NAME) <= 10,
                      "by default, a Blender without the add-on opens the file and shows the cage (the Wave above "
                      "acting), the entry's Result field saying that the add-on is off in ten characters, what 3.4.1 "
                      "draws whole there at the default width")
        obj.loop_subdivision.store_result = False
        path = os.path.join(folder, "saved-False.blend")  # the file a render farm gets by default
        check(np.array_equal(evaluated(obj)[0], positions), "after saving, the viewport shows its result again")

        # What a render farm runs: blender -b file.blend -a (frames 1 and 2), with the add-on enabled.
        record = f"""
import sys, bpy
sys.path.insert(0, {os.path.dirname(ADDON_DIR)!r})
import {os.path.basename(ADDON_DIR)} as addon
addon.register()
def frame(scene, depsgraph):
    if depsgraph.mode == 'RENDER':
        mesh = bpy.data.objects["Saved"].evaluated_get(depsgraph).data
        print("RENDERED", scene.frame_current, len(mesh.polygons), round(mesh.vertices[0].co.z, 5),
              mesh.has_custom_normals, flush=True)
bpy.app.handlers.frame_change_post.append(frame)
"""
        _, output = support.run_blender(path, record, render=(os.path.join(folder, "frame_####"), 1, 2))
        frames = [line.split()[1:] for line in output.splitlines() if line.startswith("RENDERED")]
        check(len(frames) == 2 and all(int(faces_seen) == 4 * faces for _, faces_seen, _, _ in frames)
              and frames[0][2] != frames[1][2] and all(custom == "True" for *_, custom in frames)
              and os.path.exists(os.path.join(folder, "frame_0002.png")),
              f"blender -b file -a renders the Render levels (2: {4 * faces} faces) frame by frame, following a "
              f"Wave above the entry, with the limit normals ({frames})")
    check(evaluated(obj)[1] == faces, "the viewport keeps Levels Viewport")
    support.remove(obj)
    bpy.data.objects.remove(camera)


support.clear_scene()
entry_in_stack()
stack_order()
edits()
edit_mode_with_vertex_groups()
uv_edits()
animation()
errors()
undo()
copies()
blender_apply()
saved_and_rendered()
addon.unregister()
check.finish()
