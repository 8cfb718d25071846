"""What the live entry shows with Use Limit Surface, in the viewport: Blender's own normals in place of the limit
normals while the result changes, split where the limit normals split (those edges marked sharp), and the limit
normals themselves once it is still (live.settle, which a timer runs in the interface), in renders and from Apply.

The cages are shaded smooth: the children of flat faces stay flat (as in Subdivision Surface) and show no limit
normals. The bounds on the angle between Blender's normals and the limit normals are measured (scripts in the commit
that added this test; docs/addon.md, Normals): a smooth icosphere at level 1 within 0.15 degrees, a creased cube's sides
exactly, a sphere with a creased equator within 2 degrees at level 2 (OpenSubdiv rules).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
compat, live, geometry = addon.compat, addon.live, addon.geometry
check = support.Check("test_viewport_normals")


def add_entry(obj, **arguments):
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(**arguments)
    return obj.modifiers[-1]


def shown(obj):
    return obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data


def applied(obj, **arguments):
    """The add-on's Apply of obj's own mesh with its settings, on a copy: the copy (the caller removes it)."""
    twin = support.copy_object(obj, obj.name + " twin")
    twin.modifiers.clear()
    support.apply_loop(twin, **arguments)
    support.select_only(obj)
    return twin


def angles(a, b):
    """Degrees between corresponding unit normals."""
    return np.degrees(np.arccos(np.clip((a * b).sum(axis=-1), -1.0, 1.0)))


def sharp_edges(mesh):
    """The mesh's sharp edges as a set of vertex pairs (the result's edges are numbered alike on both sides, but
    pairs do not depend on it)."""
    edges = np.sort(support.edges(mesh), axis=1)
    marked = support.read_array(mesh.edges, "use_edge_sharp", dtype=bool)
    return set(map(tuple, edges[marked].tolist()))


def auto_smooth(mesh):
    return getattr(mesh, "use_auto_smooth", True)


def compare(obj, what, bound, levels=None):
    """The viewport's result against Apply's: the same positions and faces, no custom normals, the same sharp edges
    (Apply's: where Blender split its custom normals), and normals within bound degrees."""
    mesh = shown(obj)
    twin = applied(obj) if levels is None else applied(obj, levels=levels)
    normals = compat.read_corner_normals(mesh)
    exact = compat.read_corner_normals(twin.data)
    difference = angles(normals, exact)
    same = (np.array_equal(support.positions(mesh), support.positions(twin.data))
            and len(mesh.polygons) == len(twin.data.polygons))
    check(same and not mesh.has_custom_normals and twin.data.has_custom_normals
          and sharp_edges(mesh) == sharp_edges(twin.data) and difference.max() < bound,
          f"{what}: the viewport shows Apply's positions with Blender's normals, no custom normals, sharp on Apply's "
          f"{len(sharp_edges(twin.data))} split edges, within {difference.max():.2f} degrees of the limit normals "
          f"(bound {bound}, mean {difference.mean():.3f})")
    support.remove(twin)
    return mesh


def smooth():
    """No crease, no boundary: nothing splits, Blender's vertex normals; Auto Smooth stays off as on the cage."""
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=2, radius=1.0)
    obj = support.shade_smooth(support.object_from_bmesh("Icosphere", bm))
    add_entry(obj, levels=1, rules='OPENSUBDIV')
    mesh = compare(obj, "icosphere, level 1", 0.15)
    # Auto Smooth is a setting up to 4.0 only (auto_smooth() is True from 4.1, where sharp edges always shade).
    check(not getattr(mesh, "use_auto_smooth", False) and not sharp_edges(mesh)
          and live.cache_of(obj).limit_normals is not None,
          "nothing splits: no sharp edges, Auto Smooth off as on the cage (up to 4.0), the limit normals kept for "
          "settle()")
    support.remove(obj)


def creased():
    """Crease curves: the edges on them are marked sharp (Auto Smooth on, 180 degrees), and Blender's normals split
    on the same vertices as the limit normals."""
    obj = support.shade_smooth(support.creased_cube(compat)[0])
    add_entry(obj, levels=2, rules='OPENSUBDIV')
    mesh = compare(obj, "creased cube, level 2", 0.01)
    if hasattr(mesh, "use_auto_smooth"):
        check(mesh.use_auto_smooth and abs(mesh.auto_smooth_angle - np.pi) < 1e-6,
              "Blender 3.x: Auto Smooth on at 180 degrees, so that only the marked edges split the shading")
    support.remove(obj)

    for rules, bound in (('OPENSUBDIV', 2.0), ('HOPPE94', 4.0)):
        obj = support.shade_smooth(support.object_from_bmesh("RingedSphere", support.uv_sphere(12, 8)))
        p = support.positions(obj.data)
        e = support.edges(obj.data)
        ring = np.abs(p[:, 2]) < 1e-6
        support.set_edge_creases(obj.data, np.flatnonzero(ring[e[:, 0]] & ring[e[:, 1]]), 1.0, compat)
        add_entry(obj, levels=2, rules=rules)
        compare(obj, f"sphere with a creased equator, level 2, {rules}", bound)
        support.remove(obj)


def flat_crease():
    """A crease across a flat grid: its two sides have the same limit normal there, yet the edges are marked sharp
    (found from generic positions, not these), so that the shading splits as soon as an edit bends the grid, without a
    new plan."""
    obj = support.shade_smooth(support.object_from_bmesh("FlatCrease", support.grid(6)))
    p = support.positions(obj.data)
    e = support.edges(obj.data)
    line = np.abs(p[:, 0]) < 1e-6
    support.set_edge_creases(obj.data, np.flatnonzero(line[e[:, 0]] & line[e[:, 1]]), 1.0, compat)
    add_entry(obj, levels=2, rules='OPENSUBDIV')
    mesh = shown(obj)
    positions = support.positions(mesh)
    on_line = np.abs(positions[:, 0]) < 1e-6
    marked = np.array(sorted(sharp_edges(mesh)))
    check(len(marked) and on_line[marked].all() and len(marked) == np.count_nonzero(on_line) - 1,
          f"flat: the crease's {len(marked)} child edges are marked sharp, and only they")
    builds = live.cache_of(obj).plan_builds
    p[:, 2] = 0.4 * np.abs(p[:, 0])  # a V along the crease
    obj.data.vertices.foreach_set("co", p.ravel())
    obj.data.update()
    mesh = shown(obj)
    normals = compat.read_corner_normals(mesh)
    loops = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
    inner = on_line[loops] & (np.abs(support.positions(mesh)[loops, 1]) < 0.9)
    sides = np.sign(support.positions(mesh)[:, 0][loops.reshape(-1, 3)].sum(axis=1)).repeat(3)
    left, right = normals[inner & (sides < 0)], normals[inner & (sides > 0)]
    check(live.cache_of(obj).plan_builds == builds and len(left) and len(right)
          and left[:, 0].min() > 0.3 and right[:, 0].max() < -0.3,
          "bent along the crease, without a new plan: each side of it shades with its own normal "
          f"(x components at least {left[:, 0].min():.2f} and at most {right[:, 0].max():.2f})")
    support.remove(obj)


def settled():
    """settle() writes the limit normals into the result in place: Apply's normals exactly (the same storage); the
    next edit goes back to Blender's normals, with Auto Smooth as it was, on the same plan."""
    # Bounds for the edited cages, measured: an icosphere with a vertex pulled out by a fifth of its radius, at level 1,
    # 3.0 degrees next to it; the creased cube 1.6.
    for name, cage, bound in (("icosphere", None, 3.5), ("creased cube", "creased", 2.0)):
        if cage is None:
            bm = bmesh.new()
            bmesh.ops.create_icosphere(bm, subdivisions=2, radius=1.0)
            obj = support.object_from_bmesh("Settled", bm)
        else:
            obj, _ = support.creased_cube(compat)
        support.shade_smooth(obj)
        add_entry(obj, levels=1, rules='OPENSUBDIV')
        before = auto_smooth(shown(obj))
        builds = live.cache_of(obj).plan_builds
        written = live.settle()
        mesh = shown(obj)
        twin = applied(obj)
        difference = np.abs(compat.read_corner_normals(mesh) - compat.read_corner_normals(twin.data)).max()
        check(written == 1 and mesh.has_custom_normals and difference < 1e-6 and live.settle() == 0,
              f"{name}: settle() writes the limit normals, as Apply's within {difference:.1e}; once")
        support.remove(twin)
        obj.data.vertices[0].co.z += 0.2
        obj.data.update()
        mesh = shown(obj)
        check(not mesh.has_custom_normals and auto_smooth(mesh) == before and live.cache_of(obj).plan_builds == builds,
              f"{name}: the next edit shows Blender's normals again (custom normals gone, Auto Smooth "
              f"{'on' if before else 'off'} as before), on the same plan")
        compare(obj, f"{name}, edited", bound, levels=1)
        live.settle()
        twin = applied(obj)
        difference = np.abs(compat.read_corner_normals(shown(obj)) - compat.read_corner_normals(twin.data)).max()
        check(difference < 1e-6, f"{name}: settled again after the edit: Apply's normals within {difference:.1e}")
        support.remove(twin)
        support.remove(obj)


def rendered():
    """A render's result carries the limit normals, as Apply writes them; the viewport gets Blender's back after."""
    obj = support.shade_smooth(support.creased_cube(compat)[0])
    add_entry(obj, levels=1, render_levels=2, rules='OPENSUBDIV')
    depsgraph = bpy.context.evaluated_depsgraph_get()
    live.refresh(obj, depsgraph, render=True)
    mesh = shown(obj)
    twin = applied(obj, levels=2)
    difference = np.abs(compat.read_corner_normals(mesh) - compat.read_corner_normals(twin.data)).max()
    check(mesh.has_custom_normals and len(mesh.polygons) == len(twin.data.polygons) and difference < 1e-6,
          f"a render's result (Render levels) has the limit normals, as Apply's within {difference:.1e}")
    support.remove(twin)
    live.refresh(obj, depsgraph)
    mesh = shown(obj)
    check(not mesh.has_custom_normals and len(mesh.polygons) == 8 * len(obj.data.polygons) // 2,
          "back in the viewport: Levels Viewport, Blender's normals")
    support.remove(obj)


def limit_off():
    """Without the limit surface nothing changes: no custom normals, no marks, nothing to settle."""
    obj, _ = support.creased_cube(compat)
    add_entry(obj, levels=1, rules='OPENSUBDIV', use_limit_surface=False)
    mesh = shown(obj)
    check(not mesh.has_custom_normals and not sharp_edges(mesh) and live.cache_of(obj).limit_normals is None
          and live.settle() == 0, "limit surface off: no custom normals, no sharp marks, nothing to settle")
    support.remove(obj)


support.clear_scene()
smooth()
creased()
flat_crease()
settled()
rendered()
limit_off()
addon.unregister()
check.finish()
