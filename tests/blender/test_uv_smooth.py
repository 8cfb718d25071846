"""UV Smooth: the add-on's UVs on seams against Blender's own Subdivision Surface, in every uv_smooth mode.

Each UV map is a face-varying layer: the corners of a vertex with equal UVs share one value, different UVs make a seam
(an island boundary) there. Along a seam both schemes refine the UVs with the same rules, which involve the seam
alone: linear (None, Keep Boundaries) or the cubic B-spline of the seam with its island corners kept (the other
modes); so every UV at a seam vertex is the same in Blender's result and in the add-on's, with the limit surface off
and on (both then evaluate the UV's limit). Inside islands the two schemes differ, as positions do.

Positions differ between the schemes away from creases, so vertices are matched by nearest position (a bijection,
each match much closer than the result's edges are long), then the UVs of their corners as sets, within 1e-5.

Also: the add-on's UVs are the core's own for the same mesh (`_loopsub.subdivide` welds per-corner UVs the same
way), and the modes differ where they should (the test could tell one from another).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_uv_smooth")
UV_TOLERANCE = 1e-5  # UV units (a UV map spans [0, 1])
MODES = [item.identifier for item in bpy.types.SubsurfModifier.bl_rna.properties["uv_smooth"].enum_items]


def uv_sphere():
    """Blender's UV sphere unwrapping: one seam along a meridian, and every pole triangle its own pole UV."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_uvsphere(bm, u_segments=12, v_segments=8, radius=1.0, calc_uvs=True)
    return support.object_from_bmesh("UVSphere", bm)


def uv_cube():
    """Blender's cube unwrapping (a cross of six squares: seams on seven edges), cut 3x3 per side."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=2, use_grid_fill=True)
    return support.object_from_bmesh("UVCube", bm)


def corner_uvs(mesh):
    """(per-vertex arrays of the UVs of its corners, the vertices whose corners' UVs differ by more than the
    tolerance: seam vertices). Blender evaluates each corner's UV on its own face, so equal UVs may differ in the last
    bits there."""
    uvs = support.read_array(mesh.uv_layers["UVMap"].data, "uv", 2)
    loop_vertices = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
    order = np.argsort(loop_vertices, kind="stable")
    starts = np.searchsorted(loop_vertices[order], np.arange(len(mesh.vertices) + 1))
    per_vertex = [uvs[order[starts[v]:starts[v + 1]]] for v in range(len(mesh.vertices))]
    seams = [v for v, values in enumerate(per_vertex) if np.ptp(values, axis=0).max() > UV_TOLERANCE]
    return per_vertex, np.array(seams)


def set_distance(a, b):
    """Largest distance from a UV of one set to the nearest of the other (both ways)."""
    d = np.abs(a[:, None, :] - b[None, :, :]).max(axis=2)
    return max(d.min(axis=1).max(), d.min(axis=0).max())


def match(points, cloud):
    """Index of the nearest point of cloud for each point, whether the matches make a bijection, and the largest
    ratio of a point's distance to its match over its distance to the next nearest point (a wrong match would show
    in the UVs too: UVs differ from seam vertex to seam vertex)."""
    d = np.linalg.norm(points[:, None, :] - cloud[None, :, :], axis=2)
    nearest = d.argmin(axis=1)
    two = np.sort(d, axis=1)[:, :2]
    return nearest, len(np.unique(nearest)) == len(points), float((two[:, 0] / two[:, 1]).max())


def ours(obj, level, mode, limit):
    result = support.copy_object(obj, f"{obj.name}.{mode}")
    support.apply_loop(result, levels=level, rules='OPENSUBDIV', use_limit_surface=limit, uv_smooth=mode)
    return result


def seams_coincide(make, levels):
    obj = make()
    results = {}
    for limit in (False, True):
        for level in levels:
            for mode in MODES:
                where = f"{obj.name}, {mode}, level {level}, limit {'on' if limit else 'off'}"
                blender = support.blender_subdivision(obj, level, use_limit_surface=limit, uv_smooth=mode)
                result = ours(obj, level, mode, limit)
                mine, seams = corner_uvs(result.data)
                theirs, their_seams = corner_uvs(blender)
                nearest, bijection, ratio = match(support.positions(result.data)[seams], support.positions(blender))
                worst = max(set_distance(mine[v], theirs[w]) for v, w in zip(seams, nearest))
                check(bijection and ratio < 0.75 and len(seams) == len(their_seams) and worst <= UV_TOLERANCE,
                      f"{where}: the UVs of the {len(seams)} seam vertices are Blender's (max difference "
                      f"{worst:.1e}; {len(their_seams)} seam vertices in Blender's, matched by position, each at "
                      f"most {ratio:.2f} as far from its match as from the next nearest)")
                results[limit, level, mode] = [mine[v] for v in seams]
                bpy.data.meshes.remove(blender)
                support.remove(result)
    # The modes differ on these seams (linear or B-spline, limit or not): the comparison above tells them apart.
    level = levels[-1]
    for (limit_a, a), (limit_b, b) in (((False, 'NONE'), (False, 'SMOOTH_ALL')),
                                       ((True, 'PRESERVE_BOUNDARIES'), (True, 'PRESERVE_CORNERS')),
                                       ((False, 'PRESERVE_CORNERS'), (True, 'PRESERVE_CORNERS'))):
        difference = max(set_distance(x, y) for x, y in zip(results[limit_a, level, a], results[limit_b, level, b]))
        check(difference > 100 * UV_TOLERANCE,
              f"{obj.name}, level {level}: {a} (limit {'on' if limit_a else 'off'}) and {b} (limit "
              f"{'on' if limit_b else 'off'}) differ on seams by up to {difference:.1e}")
    return obj


def as_the_core(obj):
    """The add-on's UVs, corner by corner, are the core's for the same triangles and UVs."""
    from importlib import import_module
    core = import_module(addon.__name__ + "._loopsub")
    mesh = obj.data
    mesh.calc_loop_triangles()
    loops = support.read_array(mesh.loop_triangles, "loops", 3, np.int32)
    triangles = support.read_array(mesh.loop_triangles, "vertices", 3, np.int32)
    uvs = support.read_array(mesh.uv_layers["UVMap"].data, "uv", 2)[loops]
    for mode in ('NONE', 'PRESERVE_BOUNDARIES', 'SMOOTH_ALL'):
        for limit in (False, True):
            uv_interpolation = addon.model.settings.core_name("uv_smooth", mode)
            expected = core.subdivide(support.positions(mesh), triangles, 2, rules="opensubdiv",
                                      limit_surface=limit, uv_interpolation=uv_interpolation,
                                      face_varying=uvs)["face_varying"]
            result = ours(obj, 2, mode, limit)
            got = support.read_array(result.data.uv_layers["UVMap"].data, "uv", 2).reshape(-1, 3, 2)
            check(np.array_equal(got, expected),
                  f"{obj.name}, {mode}, limit {'on' if limit else 'off'}: the UVs are the core's, corner by corner "
                  f"(max difference {np.abs(got - expected).max():.1e})")
            support.remove(result)


def defaults():
    obj = uv_sphere()
    twin = support.copy_object(obj, "Defaults")
    support.apply_loop(twin, levels=1)
    explicit = ours(obj, 1, 'PRESERVE_BOUNDARIES', True)
    same = np.array_equal(support.read_array(twin.data.uv_layers["UVMap"].data, "uv", 2),
                          support.read_array(explicit.data.uv_layers["UVMap"].data, "uv", 2))
    settings = obj.loop_subdivision
    check(same and settings.uv_smooth == 'PRESERVE_BOUNDARIES' and settings.use_limit_surface,
          "defaults as Subdivision Surface's: UV Smooth Keep Boundaries, Use Limit Surface on")
    for removed in (twin, explicit, obj):
        support.remove(removed)


support.clear_scene()
support.remove(seams_coincide(uv_sphere, (1, 2)))
support.remove(seams_coincide(uv_cube, (1,)))
sphere = uv_sphere()
as_the_core(sphere)
support.remove(sphere)
defaults()
addon.unregister()
check.finish()
