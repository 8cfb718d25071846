"""What the live entry shows with Use Limit Surface: the limit normals themselves after every update — adding the
entry, each edit, each frame of playback, a setting's change, a render — equal to what Apply writes (within 1e-6),
with no extra call and no settling step, in every Blender version; and nothing of that with the limit surface off.

Each cage is checked against the add-on's Apply of the same mesh (a copy): positions, faces and the normals Blender
shades with (compat.read_corner_normals). The cages cover each way the add-on writes them: a smooth icosphere and an
open grid (one normal per vertex; the grid's boundary vertices take their one side's), a creased cube and a sphere
with a creased equator (sides that split fans), a cage with flat faces (whose corners keep Blender's own normal) and
one with marked sharp edges (the corners on them keep Blender's too).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
compat, live = support.blender_access(addon), addon.live.engine
check = support.Check("test_viewport_normals")


def add_entry(obj, **arguments):
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(**arguments)
    return obj.modifiers[-1]


def shown(obj):
    return obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data


def applied(obj, **arguments):
    """The add-on's Apply of obj's mesh as the entry sees it (the modifiers above the entry applied first, with
    Blender's own Apply), on a copy: the copy (the caller removes it)."""
    twin = support.copy_object(obj, obj.name + " twin")
    for modifier in list(twin.modifiers):
        if modifier.type == 'NODES':
            twin.modifiers.remove(modifier)
    for modifier in list(twin.modifiers):
        with bpy.context.temp_override(object=twin, active_object=twin):
            bpy.ops.object.modifier_apply(modifier=modifier.name)
    support.apply_loop(twin, **arguments)
    support.select_only(obj)
    return twin


def same_as_apply(obj, what, **arguments):
    """The viewport's result against Apply's: the same positions and faces, and the same normals within 1e-6."""
    mesh = shown(obj)
    twin = applied(obj, **arguments)
    normals = compat.read_corner_normals(mesh)
    exact = compat.read_corner_normals(twin.data)
    same = (np.array_equal(support.positions(mesh), support.positions(twin.data))
            and len(mesh.polygons) == len(twin.data.polygons) and normals.shape == exact.shape)
    difference = np.abs(normals - exact).max() if same else np.inf
    check(same and difference < 1e-6,
          f"{what}: the viewport shows Apply's positions, faces and normals (within {difference:.1e})")
    support.remove(twin)


def icosphere(name):
    return support.shade_smooth(support.object_from_bmesh(name, support.icosphere()))


def ringed_sphere():
    obj = support.shade_smooth(support.object_from_bmesh("RingedSphere", support.uv_sphere(12, 8)))
    p, e = support.positions(obj.data), support.edges(obj.data)
    ring = np.abs(p[:, 2]) < 1e-6
    support.set_edge_creases(obj.data, np.flatnonzero(ring[e[:, 0]] & ring[e[:, 1]]), 1.0, compat)
    return obj


def half_flat():
    """An icosphere whose upper half is shaded flat: the children of those faces keep their face normals."""
    obj = icosphere("HalfFlat")
    centres = support.read_array(obj.data.polygons, "center", 3)
    obj.data.polygons.foreach_set("use_smooth", centres[:, 2] < 0)
    obj.data.update()
    return obj


def sharp_marked():
    """An icosphere with the edges of its upper cap marked sharp: the corners on them keep Blender's own normal."""
    obj = icosphere("SharpMarked")
    p, e = support.positions(obj.data), support.edges(obj.data)
    marked = (p[e[:, 0], 2] > 0.5) & (p[e[:, 1], 2] > 0.5)
    obj.data.edges.foreach_set("use_edge_sharp", marked)
    obj.data.update()
    return obj


def flat_faces_flat(obj, what):
    """The result's flat faces shade with their face normals (worked out here from the positions), as Blender shades
    flat faces of its own."""
    mesh = shown(obj)
    flat = ~support.read_array(mesh.polygons, "use_smooth", dtype=bool)
    if not flat.any():
        return
    p = support.positions(mesh).astype(np.float64)
    t = support.read_array(mesh.loops, "vertex_index", dtype=np.int32).reshape(-1, 3)[flat]
    face = np.cross(p[t[:, 1]] - p[t[:, 0]], p[t[:, 2]] - p[t[:, 0]])
    face /= np.linalg.norm(face, axis=1, keepdims=True)
    corners = compat.read_corner_normals(mesh).reshape(-1, 3, 3)[flat]
    difference = np.abs(corners - face[:, None, :]).max()
    check(difference < 1e-6, f"{what}: the flat faces shade with their face normals (within {difference:.1e})")


CAGES = (
    ("icosphere", lambda: icosphere("Icosphere"), 'OPENSUBDIV'),
    ("open grid", lambda: support.shade_smooth(support.object_from_bmesh("Grid", support.grid(6))), 'OPENSUBDIV'),
    ("creased cube", lambda: support.shade_smooth(support.creased_cube(compat)[0]), 'OPENSUBDIV'),
    ("sphere with a creased equator", ringed_sphere, 'HOPPE94'),
    ("icosphere, upper half flat", half_flat, 'OPENSUBDIV'),
    ("icosphere, upper cap marked sharp", sharp_marked, 'OPENSUBDIV'),
)


def every_edit():
    """After adding the entry and after each edit (one vertex, then every vertex), the result is updated in place on
    the same plan and shows Apply's normals; a change of Levels Viewport too."""
    for name, make, rules in CAGES:
        obj = make()
        add_entry(obj, levels=1, rules=rules)
        same_as_apply(obj, f"{name}, added", levels=1, rules=rules)
        builds = live.cache_of(obj).plan_builds
        obj.data.vertices[0].co.z += 0.2
        obj.data.update()
        same_as_apply(obj, f"{name}, one vertex moved", levels=1, rules=rules)
        p = support.positions(obj.data)
        p *= 1.0 + 0.1 * np.sin(7.0 * p[:, [1, 2, 0]])
        obj.data.vertices.foreach_set("co", p.ravel())
        obj.data.update()
        same_as_apply(obj, f"{name}, every vertex moved", levels=1, rules=rules)
        flat_faces_flat(obj, name)
        check(live.cache_of(obj).plan_builds == builds, f"{name}: the edits reused the plan (updated in place)")
        obj.loop_subdivision.levels = 2
        same_as_apply(obj, f"{name}, Levels Viewport 2", levels=2, rules=rules)
        support.remove(obj)


def bent_flat_crease():
    """A crease across a flat grid, whose sides have one normal while it is flat: an edit that bends the grid along
    it, without a new plan, gives each side its own normal at once."""
    obj = support.shade_smooth(support.object_from_bmesh("FlatCrease", support.grid(6)))
    p, e = support.positions(obj.data), support.edges(obj.data)
    line = np.abs(p[:, 0]) < 1e-6
    support.set_edge_creases(obj.data, np.flatnonzero(line[e[:, 0]] & line[e[:, 1]]), 1.0, compat)
    add_entry(obj, levels=2, rules='OPENSUBDIV')
    same_as_apply(obj, "flat crease", levels=2)
    builds = live.cache_of(obj).plan_builds
    p[:, 2] = 0.4 * np.abs(p[:, 0])  # a V along the crease
    obj.data.vertices.foreach_set("co", p.ravel())
    obj.data.update()
    same_as_apply(obj, "flat crease, bent", levels=2)
    mesh = shown(obj)
    normals = compat.read_corner_normals(mesh)
    positions = support.positions(mesh)
    loops = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
    inner = (np.abs(positions[loops, 0]) < 1e-6) & (np.abs(positions[loops, 1]) < 0.9)
    sides = np.sign(positions[:, 0][loops.reshape(-1, 3)].sum(axis=1)).repeat(3)
    left, right = normals[inner & (sides < 0)], normals[inner & (sides > 0)]
    check(live.cache_of(obj).plan_builds == builds and len(left) and len(right)
          and left[:, 0].min() > 0.3 and right[:, 0].max() < -0.3,
          "bent along the crease, without a new plan: each side of it shades with its own normal "
          f"(x components at least {left[:, 0].min():.2f} and at most {right[:, 0].max():.2f})")
    support.remove(obj)


def playback():
    """A Wave modifier above the entry, animated by time: every frame's result shows Apply's normals of that frame's
    input."""
    obj = icosphere("Waved")
    wave = obj.modifiers.new("Wave", 'WAVE')
    wave.height = 0.2
    add_entry(obj, levels=2, rules='OPENSUBDIV')
    scene = bpy.context.scene
    for frame in (3, 4, 9):
        scene.frame_set(frame)
        same_as_apply(obj, f"Wave-deformed icosphere, frame {frame}", levels=2)
    scene.frame_set(1)
    support.remove(obj)


def rendered():
    """A render's result (Render levels) and the viewport's after it (Levels Viewport) both have Apply's normals."""
    obj = support.shade_smooth(support.creased_cube(compat)[0])
    add_entry(obj, levels=1, render_levels=2, rules='OPENSUBDIV')
    depsgraph = bpy.context.evaluated_depsgraph_get()
    live.refresh(obj, depsgraph, render=True)
    same_as_apply(obj, "a render's result, Render levels", levels=2)
    live.refresh(obj, depsgraph)
    same_as_apply(obj, "back in the viewport, Levels Viewport", levels=1)
    support.remove(obj)


def limit_off():
    """Without the limit surface the result has Blender's own normals: no custom normals."""
    obj, _ = support.creased_cube(compat)
    add_entry(obj, levels=1, rules='OPENSUBDIV', use_limit_surface=False)
    obj.data.vertices[0].co.z += 0.2
    obj.data.update()
    mesh = shown(obj)
    check(not mesh.has_custom_normals and not compat.has_free_normals(mesh),
          "limit surface off: no custom normals after an edit")
    support.remove(obj)


support.clear_scene()
every_edit()
bent_flat_crease()
playback()
rendered()
limit_off()
addon.unregister()
check.finish()
