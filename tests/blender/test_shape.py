"""Shape of the Loop result against Blender's own Subdivision Surface, and the invariants of the result.

Away from crease curves the two schemes differ (Loop on triangles, Catmull-Clark on the same triangles), so the fair
comparison there is a distance between the surfaces relative to the model's size (RULES.md §4): every vertex of the
add-on's level-3 result (OpenSubdiv-compatible rules, Use Limit Surface on: its vertices lie on Loop's limit surface)
to the nearest point of Blender's level-3 limit surface (use_limit_surface on, creases on), divided by the
bounding-box diagonal.

The bound, measured on Blender 3.4.1 (max and mean over vertices / diagonal, level 3):
    icosphere (2 subdivisions, smooth)                       max 0.0046   mean 0.0037
    Suzanne (triangulated, open boundaries)                  max 0.0051   mean 0.0007
    box cut 2x2 per side, 4 vertical creases                 max 0.0177   mean 0.0054
(Without the limit surface, the level-3 control points measured 0.0042, 0.0047 and 0.0165.) The distance is the
difference of the two schemes' limit surfaces, different surfaces of the same cage (Catmull-Clark on triangles first
splits each into three quads). They are close on smooth, fine cages and farthest where a coarse cage turns a right
angle without a crease: the box's maximum sits on its rounded, uncreased horizontal sides, between the vertical
creases. The bound, 0.025, is the largest measurement with a 40% margin for differences between Blender builds; a
wrong mask, a missed crease or a scrambled triangle moves vertices by several percent.

Also: 4^L faces per triangle, the Euler characteristic kept, and normals pointing the way Blender's result does.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402
from mathutils.bvhtree import BVHTree  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_shape")
SHAPE_BOUND = 0.025  # of the bounding-box diagonal, see above
# Measured: 100% on the icosphere and the box; on Suzanne 99.90% at level 1 (4 of 3,872 faces), where eyeballs
# touch their sockets and the nearest face of Blender's result lies on the other sheet. A flipped or scrambled winding
# gives about 0% or 50%.
NORMALS_AGREEING = 0.995


def icosphere():
    return support.object_from_bmesh("Icosphere", support.icosphere())


def suzanne():
    bm = bmesh.new()
    bmesh.ops.create_monkey(bm)
    # Fixed, not Beauty: Beauty gives Suzanne two triangles on the same three vertices, whose non-manifold edges stay
    # sharp (test_apply checks that it applies) and would show in this distance as a fold.
    bmesh.ops.triangulate(bm, faces=bm.faces[:], quad_method='FIXED')
    return support.object_from_bmesh("Suzanne", bm, triangulate=False)


def creased_box():
    """A cube cut 2x2 per side with only its four vertical sides creased: each crease ends in a dart at a cube corner,
    top and bottom round off."""
    obj = support.object_from_bmesh("CreasedBox", support.cube("CreasedBox", subdivisions=1))
    p = support.positions(obj.data)
    e = support.edges(obj.data)
    vertical = (np.abs(np.abs(p[:, 0]) - 1.0) < 1e-6) & (np.abs(np.abs(p[:, 1]) - 1.0) < 1e-6)
    support.set_edge_creases(obj.data, np.flatnonzero(vertical[e[:, 0]] & vertical[e[:, 1]]), 1.0,
                             support.blender_access(addon))
    return obj


def bvh(mesh):
    polygons = [tuple(polygon.vertices) for polygon in mesh.polygons]
    return BVHTree.FromPolygons(support.positions(mesh).tolist(), polygons)


def face_normals(mesh):
    return support.read_array(mesh.polygons, "normal", 3)


def face_centers(mesh):
    return support.read_array(mesh.polygons, "center", 3)


def euler(mesh):
    return len(mesh.vertices) - len(mesh.edges) + len(mesh.polygons)


def loop_result(obj, levels):
    result = support.copy_object(obj, f"{obj.name}.loop{levels}")
    support.apply_loop(result, levels=levels, rules='OPENSUBDIV', boundary='SMOOTH', use_limit_surface=True)
    return result


def shape(obj):
    diagonal = support.bbox_diagonal(support.positions(obj.data))
    limit = support.blender_subdivision(obj, 3, use_limit_surface=True)
    tree = bvh(limit)
    ours = loop_result(obj, 3)
    distances = np.array([tree.find_nearest(p)[3] for p in support.positions(ours.data).tolist()]) / diagonal
    check(distances.max() < SHAPE_BOUND,
          f"{obj.name}: level-3 Loop vs Blender's limit surface: max {distances.max():.5f}, "
          f"mean {distances.mean():.5f} of the diagonal (bound {SHAPE_BOUND})")
    bpy.data.meshes.remove(limit)
    remove(ours)


def invariants(obj, levels=(1, 2, 3)):
    cage = obj.data
    triangles = len(cage.polygons)  # the test meshes are triangulated
    for level in levels:
        ours = loop_result(obj, level)
        mesh = ours.data
        check(len(mesh.polygons) == triangles * 4 ** level,
              f"{obj.name}, level {level}: {len(mesh.polygons)} faces = {triangles}·4^{level}")
        check(euler(mesh) == euler(cage), f"{obj.name}, level {level}: Euler characteristic {euler(mesh)} kept")
        check(not mesh.validate(verbose=True), f"{obj.name}, level {level}: the result is a valid Blender mesh")

        # Every face turns the way Blender's own result turns there: the normal of the nearest face of Blender's
        # result (same level, no limit surface) points the same way.
        blender = support.blender_subdivision(obj, level)
        tree = bvh(blender)
        normals = face_normals(mesh)
        nearest = [tree.find_nearest(c) for c in face_centers(mesh).tolist()]
        dots = np.array([np.dot(hit[1], n) for hit, n in zip(nearest, normals.tolist())])
        agreeing = np.mean(dots > 0)
        check(agreeing >= NORMALS_AGREEING, f"{obj.name}, level {level}: {agreeing:.2%} of the face normals point "
                                            f"the way Blender's do (smallest cosine {dots.min():.3f})")
        bpy.data.meshes.remove(blender)
        remove(ours)


def remove(obj):
    mesh = obj.data
    bpy.data.objects.remove(obj)
    bpy.data.meshes.remove(mesh)


support.clear_scene()
for make in (icosphere, suzanne, creased_box):
    model = make()
    shape(model)
    invariants(model)
    remove(model)
addon.unregister()
check.finish()
