"""Crease tags written as attributes: "loop_crease" (boolean, edges) and "loop_vertex_type" (integer, points:
0 smooth, 1 dart, 2 regular crease, 3 irregular crease, 4 corner, 5 cone), checked against classifications derived
here from the cage (RULES.md §1).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
compat = support.blender_access(addon)
check = support.Check("test_tags")
SMOOTH, DART, REGULAR, IRREGULAR, CORNER, CONE = range(6)


def tags(obj):
    mesh = obj.data
    crease = mesh.attributes["loop_crease"]
    types = mesh.attributes["loop_vertex_type"]
    check((crease.domain, crease.data_type, types.domain, types.data_type) == ('EDGE', 'BOOLEAN', 'POINT', 'INT'),
          f"{obj.name}: loop_crease is a boolean edge attribute, loop_vertex_type an integer point attribute")
    return support.read_array(crease.data, "value", dtype=bool), support.read_array(types.data, "value", dtype=np.int32)


def refresh(obj, **settings):
    for name, value in settings.items():
        setattr(obj.loop_subdivision, name, value)
    support.select_only(obj)
    return bpy.ops.object.loop_subdivision_refresh_tags()


def expected_types(obj, threshold):
    """Seed classification from the cage: crease edges are weights >= threshold and boundary edges."""
    weights = compat.read_edge_creases(obj.data)
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    types = []
    for vert in bm.verts:
        creases = [e for e in vert.link_edges if weights[e.index] >= threshold or e.is_boundary]
        if len(creases) >= 3:
            types.append(CORNER)
        elif len(creases) == 2:
            types.append(REGULAR if support.is_regular_crease(vert, creases) else IRREGULAR)
        else:
            types.append(len(creases))  # 0 smooth, 1 dart
    bm.free()
    return np.array(types)


def creased_cube():
    obj, sides = support.creased_cube(compat)
    support.set_edge_creases(obj.data, sides[:1], 0.4, compat)  # half a side below the threshold
    return obj, sides


def tagging():
    obj, sides = creased_cube()
    weights = compat.read_edge_creases(obj.data)
    refresh(obj, rules='HOPPE94', crease_threshold=0.5)
    crease, types = tags(obj)
    check(np.array_equal(crease, weights >= 0.5), "seed rules: crease edges are the weights at or above the threshold")
    expected = expected_types(obj, 0.5)
    check(np.array_equal(types, expected),
          f"seed rules: vertex types {np.bincount(types, minlength=6).tolist()} (smooth, dart, regular, irregular, "
          f"corner, cone) as classified by hand {np.bincount(expected, minlength=6).tolist()}")
    check((types == DART).sum() == 1 and (types == CORNER).sum() == 7,
          "seed rules: the half side below the threshold leaves a dart at its middle end and one corner fewer")

    refresh(obj, rules='OPENSUBDIV')
    crease, types = tags(obj)
    check(np.array_equal(crease, weights > 0), "OpenSubdiv rules: every positive weight is a (semi-sharp) crease")
    check((types == CORNER).sum() == 8 and (types == DART).sum() == 0,
          f"OpenSubdiv rules: the cube's 8 corners are corners, no darts {np.bincount(types, minlength=6).tolist()}")

    refresh(obj, rules='HOPPE94', use_creases=False)
    crease, types = tags(obj)
    check(not crease.any() and (types == SMOOTH).all(), "Use Creases off: no creases, every vertex smooth")
    remove(obj)

    sphere = support.object_from_bmesh("Sphere", support.uv_sphere(8, 6))
    p = support.positions(sphere.data)
    top = int(np.argmax(p[:, 2]))
    bottom = int(np.argmin(p[:, 2]))
    sphere.vertex_groups.new(name="Cones").add([top], 1.0, 'REPLACE')
    corners = np.zeros(len(p), dtype=np.float32)
    corners[bottom] = 1.0
    compat.write_vertex_creases(sphere.data, corners)
    refresh(sphere, rules='HOPPE94', cone_group="Cones", crease_threshold=0.5, use_creases=True)
    _, types = tags(sphere)
    check(types[top] == CONE and types[bottom] == CORNER and (np.delete(types, [top, bottom]) == SMOOTH).all(),
          "seed rules: the cone group's vertex is a cone, the vertex crease a corner, the rest smooth")
    refresh(sphere, rules='OPENSUBDIV')
    _, types = tags(sphere)
    check(types[top] == SMOOTH and types[bottom] == CORNER, "OpenSubdiv rules: no cones; the vertex crease a corner")
    remove(sphere)

    grid = support.object_from_bmesh("Grid", support.grid(3))
    refresh(grid, rules='OPENSUBDIV', boundary='KEEP_CORNERS')
    crease, types = tags(grid)
    counts = support.edge_face_counts(grid.data)
    bm = bmesh.new()
    bm.from_mesh(grid.data)
    single_face = np.array([len(v.link_faces) == 1 for v in bm.verts])
    bm.free()
    check(np.array_equal(crease, counts == 1), "boundary edges are crease edges")
    check(np.array_equal(types == CORNER, single_face),
          "Keep Corners: boundary vertices with one face are corners, no others")
    remove(grid)


def remove(obj):
    mesh = obj.data
    bpy.data.objects.remove(obj)
    bpy.data.meshes.remove(mesh)


support.clear_scene()
tagging()
addon.unregister()
check.finish()
