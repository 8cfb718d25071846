"""The apply operator: what it keeps, what it writes, how it fails, and undo.

bpy.ops.object.loop_subdivision_apply on cubes carrying every kind of data the add-on moves: triangulation reported,
materials and flat/smooth shading per parent face, UV seams (UV discontinuities and seam marks), vertex-group weights
and point colours interpolated as vertex channels (a quantity linear in the position stays that linear function of the
new positions, since every rule's weights sum to one), corner colours per face, child crease weights (OpenSubdiv:
decremented sharpness mapped back through 10·c²; seed rules: the weight kept), arguments overriding the panel,
the active object only, bad meshes left untouched with an error report, and undo.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
compat = support.blender_access(addon)
check = support.Check("test_apply")


def uv_cube(name, triangulate=True):
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    return support.object_from_bmesh(name, bm, triangulate=triangulate)


def parent_polygons(mesh):
    """Cage polygon of each cage triangle (Blender's tessellation, as the add-on uses it)."""
    mesh.calc_loop_triangles()
    return support.read_array(mesh.loop_triangles, "polygon_index", dtype=np.int32)


def polygon_values(mesh, prop, dtype):
    return support.read_array(mesh.polygons, prop, dtype=dtype)


def uv_discontinuities(mesh, uv_name):
    """Edges whose two faces give one of its vertices different UVs (UV seams), as a set of vertex pairs."""
    uvs = support.read_array(mesh.uv_layers[uv_name].data, "uv", 2)
    seen = {}
    for polygon in mesh.polygons:
        loops = list(polygon.loop_indices)
        for i, loop in enumerate(loops):
            nxt = loops[(i + 1) % len(loops)]
            a, b = mesh.loops[loop].vertex_index, mesh.loops[nxt].vertex_index
            key = (min(a, b), max(a, b))
            ends = {a: tuple(uvs[loop]), b: tuple(uvs[nxt])}
            seen.setdefault(key, []).append(ends)
    return {key for key, sides in seen.items()
            if len(sides) == 2 and any(np.abs(np.subtract(sides[0][v], sides[1][v])).max() > 1e-6 for v in key)}


def edge_flags(mesh, prop):
    e = support.edges(mesh)[support.read_array(mesh.edges, prop, dtype=bool)]
    return {(min(a, b), max(a, b)) for a, b in e.tolist()}


def group_weights(obj, name):
    index = obj.vertex_groups[name].index
    weights = np.zeros(len(obj.data.vertices))
    for vertex in obj.data.vertices:
        for element in vertex.groups:
            if element.group == index:
                weights[vertex.index] = element.weight
    return weights


def attribute_values(mesh, name, width):
    return support.read_array(mesh.attributes[name].data, "color", width)


def run_apply(obj, **arguments):
    support.select_only(obj)
    return support.capture_output(lambda: bpy.ops.object.loop_subdivision_apply(**arguments))


# --- triangulation, per-face data, panel settings -----------------------------------------------------------------

def faces_and_shading():
    obj = uv_cube("QuadCube", triangulate=False)
    mesh = obj.data
    for name in ("Red", "Green", "Blue"):
        mesh.materials.append(bpy.data.materials.new(name))
    mesh.polygons.foreach_set("material_index", np.arange(len(mesh.polygons), dtype=np.int32) % 3)
    mesh.polygons.foreach_set("use_smooth", np.arange(len(mesh.polygons)) % 2 == 0)
    cage_polygons = parent_polygons(mesh)
    cage_materials = polygon_values(mesh, "material_index", np.int32)
    cage_smooth = polygon_values(mesh, "use_smooth", bool)
    cage_normals = support.read_array(mesh.polygons, "normal", 3)
    name = mesh.name
    support.select_only(obj)
    # The result keeps per-face shading with the limit surface on too (test_limit.flat_faces).
    bpy.ops.object.loop_subdivision_add(levels=2, use_limit_surface=False)
    result, output = run_apply(obj)  # no argument given: the modifier's settings count
    check(result == {'FINISHED'}, "apply finishes on a quad cube")
    check("triangulated 6 non-triangle faces" in output, "apply reports that it triangulated the 6 quads first")
    mesh = obj.data
    check(len(mesh.polygons) == 12 * 4 ** 2, f"the panel's 2 levels are used: {len(mesh.polygons)} faces")
    parents = cage_polygons[np.arange(len(mesh.polygons)) // 16]
    check(np.array_equal(polygon_values(mesh, "material_index", np.int32), cage_materials[parents]),
          "every face keeps its parent face's material index")
    check(np.array_equal(polygon_values(mesh, "use_smooth", bool), cage_smooth[parents]),
          "every face keeps its parent face's flat/smooth shading")
    facing = np.einsum("ij,ij->i", support.read_array(mesh.polygons, "normal", 3), cage_normals[parents])
    check((facing > 0.5).all(), "every face faces the way its quad does: Blender's triangles of the quads are taken "
          f"with their corners in order (least cosine {facing.min():.2f})")
    check(len(mesh.materials) == 3, "the material slots are kept")
    check(mesh.name == name and bpy.data.meshes.get(name) == mesh, "the mesh keeps its name; the old data is gone")
    check(not obj.modifiers, "applying removes the Loop Subdivision modifier")
    check({"loop_crease", "loop_vertex_type"} <= set(mesh.attributes.keys()), "apply refreshes the tags")
    check(not mesh.validate(verbose=True), "the result is a valid mesh")
    support.remove(obj)


# --- UVs, seams ------------------------------------------------------------------------------------------------

def uv_seams(triangulate):
    """Seams and sharp marks on a cube of triangles, and on one of quads, whose diagonals (Blender's triangulation,
    no mesh edges) must leave no mark on the edges along them."""
    obj = uv_cube("UVCube", triangulate)
    mesh = obj.data
    uv_name = mesh.uv_layers.active.name
    mesh.uv_layers.new(name="Second")
    seams = uv_discontinuities(mesh, uv_name)
    seam_flags = np.array([(min(a, b), max(a, b)) in seams for a, b in support.edges(mesh).tolist()])
    mesh.edges.foreach_set("use_seam", seam_flags)
    sharp = np.zeros(len(mesh.edges), dtype=bool)
    sharp[0] = True
    mesh.edges.foreach_set("use_edge_sharp", sharp)
    mesh.uv_layers.active = mesh.uv_layers[uv_name]
    level = 2
    run_apply(obj, levels=level, rules='OPENSUBDIV')
    mesh = obj.data
    result_seams = uv_discontinuities(mesh, uv_name)
    kind = "triangles" if triangulate else "quads"
    check(len(seams) > 0 and len(result_seams) == len(seams) * 2 ** level,
          f"{kind}: UV seams stay seams: {len(seams)} seam edges become {len(result_seams)} = {len(seams)}·2^{level}")
    check(edge_flags(mesh, "use_seam") == result_seams, f"{kind}: seam marks follow the seams onto the child edges")
    check(len(edge_flags(mesh, "use_edge_sharp")) == 2 ** level, f"{kind}: a sharp edge's child edges are sharp")
    check([uv.name for uv in mesh.uv_layers] == [uv_name, "Second"] and mesh.uv_layers.active.name == uv_name,
          "UV maps are kept, with the active one")
    support.remove(obj)


# --- vertex channels: groups and colours ------------------------------------------------------------------------

def vertex_channels(rules):
    obj = uv_cube(f"Channels{rules}")
    mesh = obj.data
    p = support.positions(mesh)
    linear = obj.vertex_groups.new(name="Linear")
    top = obj.vertex_groups.new(name="Top")
    for i, x in enumerate(p[:, 0]):
        linear.add([i], float((x + 1) / 2), 'REPLACE')
    top.add([int(i) for i in np.flatnonzero(p[:, 2] > 0)], 1.0, 'REPLACE')
    obj.vertex_groups.active_index = top.index
    colors = mesh.color_attributes.new("PointColor", 'FLOAT_COLOR', 'POINT')
    rgba = np.concatenate([(p + 1) / 2, np.ones((len(p), 1))], axis=1).astype(np.float32)
    colors.data.foreach_set("color", rgba.ravel())
    corner = mesh.color_attributes.new("FaceColor", 'BYTE_COLOR', 'CORNER')
    palette = np.array([[1, 0, 0, 1], [0, 1, 0, 1], [0, 0, 1, 1], [1, 1, 0, 1]], dtype=np.float32)
    loop_faces = np.repeat(np.arange(len(mesh.polygons)), 3)  # triangles: 3 loops each, in order
    corner.data.foreach_set("color", palette[loop_faces % 4].ravel())
    mesh.color_attributes.active_color = colors
    creases = np.zeros(len(mesh.edges), dtype=np.float32)
    creases[:4] = 1.0  # crease and corner rules must keep the channels affine too
    compat.write_edge_creases(mesh, creases)

    run_apply(obj, levels=2, rules=rules)
    mesh = obj.data
    p = support.positions(mesh).astype(np.float64)
    weights = group_weights(obj, "Linear")
    check(np.abs(weights - (p[:, 0] + 1) / 2).max() < 1e-5,
          f"{rules}: vertex-group weights are interpolated as vertex channels "
          f"(linear in x before, linear in x after: max error {np.abs(weights - (p[:, 0] + 1) / 2).max():.1e})")
    check([g.name for g in obj.vertex_groups] == ["Linear", "Top"] and obj.vertex_groups.active_index == 1,
          f"{rules}: vertex groups keep their names, order and active group")
    top_weights = group_weights(obj, "Top")
    check(top_weights.min() >= 0 and top_weights.max() <= 1 and np.all(top_weights[p[:, 2] < -0.99] == 0),
          f"{rules}: a partial group stays in [0, 1] and away from vertices it never reached")
    result_rgba = attribute_values(mesh, "PointColor", 4)
    check(np.abs(result_rgba[:, :3] - (p + 1) / 2).max() < 1e-5,
          f"{rules}: point colours are interpolated as vertex channels")
    result_corner = attribute_values(mesh, "FaceColor", 4).reshape(-1, 3, 4)
    expected = palette[(np.arange(len(mesh.polygons)) // 16) % 4]
    check(np.abs(result_corner - expected[:, None, :]).max() < 1e-2,
          f"{rules}: corner colours stay with their faces (byte colours)")
    check(mesh.color_attributes.active_color.name == "PointColor", f"{rules}: the active colour attribute is kept")
    support.remove(obj)


# --- creases ----------------------------------------------------------------------------------------------------

def creases_written():
    for rules, levels, expected_weight in (('OPENSUBDIV', 1, math.sqrt((3.6 - 1) / 10)),
                                           ('OPENSUBDIV', 2, math.sqrt((3.6 - 2) / 10)),
                                           ('HOPPE94', 2, 0.6)):
        obj = uv_cube("Creases")
        mesh = obj.data
        p = support.positions(mesh)
        e = support.edges(mesh)
        # The cube's 12 sides (not the diagonals the triangulation added) get crease 0.6, one corner crease 1.0.
        sides = np.flatnonzero(np.abs(p[e[:, 0]] - p[e[:, 1]]).max(axis=1).round(6) ==
                               np.linalg.norm(p[e[:, 0]] - p[e[:, 1]], axis=1).round(6))
        weights = np.zeros(len(e), dtype=np.float32)
        weights[sides] = 0.6
        compat.write_edge_creases(mesh, weights)
        corner_weights = np.zeros(len(p), dtype=np.float32)
        corner_weights[0] = 1.0
        compat.write_vertex_creases(mesh, corner_weights)
        run_apply(obj, levels=levels, rules=rules)
        result = compat.read_edge_creases(obj.data)
        creased = result[result > 0]
        check(len(sides) == 12 and len(creased) == 12 * 2 ** levels
              and np.abs(creased - expected_weight).max() < 1e-6,
              f"{rules}, level {levels}: the 12 creased sides give {len(creased)} child crease edges of weight "
              f"{expected_weight:.4f} (got {np.unique(creased.round(4)).tolist()})")
        vertex_creases = compat.read_vertex_creases(obj.data)
        check(vertex_creases[0] == 1.0 and np.count_nonzero(vertex_creases) == 1,
              f"{rules}, level {levels}: the corner keeps its vertex crease 1.0 (infinitely sharp)")
        support.remove(obj)


def loose_geometry():
    """A creased wire edge and a lone vertex beside the surface: the edge is left out with a warning (the core only
    takes creases on its triangles' edges), the vertices stay."""
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=2.0)
    bm.edges.new((bm.verts.new((3, 0, 0)), bm.verts.new((4, 0, 0))))
    bm.verts.new((5, 0, 0))
    obj = support.object_from_bmesh("Loose", bm)
    weights = compat.read_edge_creases(obj.data)
    weights[:] = 1.0
    compat.write_edge_creases(obj.data, weights)
    result, output = run_apply(obj, levels=1, rules='OPENSUBDIV')
    mesh = obj.data
    check(result == {'FINISHED'} and "1 loose edge (in no face) is not carried over" in output,
          "a creased loose edge is left out with a warning (one edge, in the singular)")
    check(np.allclose(support.positions(mesh)[8:11], [[3, 0, 0], [4, 0, 0], [5, 0, 0]]),
          "loose vertices keep their places and indices")
    support.remove(obj)


# --- attributes of other types ------------------------------------------------------------------------------------

def other_attributes():
    """Integer and boolean point attributes and edge attributes, kept as Subdivision Surface keeps them."""
    obj = uv_cube("Attributes")
    mesh = obj.data
    num_vertices, cage_edges = len(mesh.vertices), support.edges(mesh)
    constant = mesh.attributes.new("Constant", 'INT', 'POINT')
    constant.data.foreach_set("value", np.full(num_vertices, 7, np.int32))
    marked = mesh.attributes.new("Marked", 'BOOLEAN', 'POINT')
    flags = np.zeros(num_vertices, bool)
    flags[0] = True
    marked.data.foreach_set("value", flags)
    far = int(np.argmax(np.linalg.norm(support.positions(mesh) - support.positions(mesh)[0], axis=1)))
    edge_ids = mesh.attributes.new("EdgeId", 'FLOAT', 'EDGE')
    edge_ids.data.foreach_set("value", np.arange(1, len(cage_edges) + 1, dtype=np.float32))
    run_apply(obj, levels=1, rules='OPENSUBDIV')
    mesh = obj.data
    ints = support.read_array(mesh.attributes["Constant"].data, "value", dtype=np.int32)
    check(mesh.attributes["Constant"].data_type == 'INT' and np.all(ints == 7),
          "an integer point attribute stays an integer (a constant stays that constant)")
    bools = support.read_array(mesh.attributes["Marked"].data, "value", dtype=bool)
    check(bools[0] and not bools[far], "a boolean point attribute stays true where it was and false far from it")
    ids = support.read_array(mesh.attributes["EdgeId"].data, "value").astype(np.int64)
    result_edges = support.edges(mesh)
    on_cage = ids > 0
    ends_ok = all(set(cage_edges[i - 1]) & set(result_edges[k])
                  for k, i in zip(np.flatnonzero(on_cage), ids[on_cage]))
    check(np.array_equal(np.bincount(ids[on_cage], minlength=len(cage_edges) + 1)[1:], np.full(len(cage_edges), 2))
          and ends_ok and np.count_nonzero(~on_cage) == 3 * 12,
          "an edge attribute passes to the two halves of each cage edge (which keep an end of it); edges inside "
          "faces get zero")
    support.remove(obj)


def triangulated_suzanne():
    """Ctrl T (Beauty) gives Suzanne two faces on the same three vertices: OpenSubdiv and Subdivision Surface
    subdivide it, their edges non-manifold and sharp; so does the add-on, with a warning."""
    for rules in ('OPENSUBDIV', 'HOPPE94'):
        bm = bmesh.new()
        bmesh.ops.create_monkey(bm)
        bmesh.ops.triangulate(bm, faces=bm.faces[:], quad_method='BEAUTY', ngon_method='BEAUTY')
        obj = support.object_from_bmesh(f"Suzanne{rules}", bm, triangulate=False)
        faces = len(obj.data.polygons)
        result, output = run_apply(obj, levels=2, rules=rules)
        check(result == {'FINISHED'} and len(obj.data.polygons) == 16 * faces
              and np.isfinite(support.positions(obj.data)).all() and "lie on the same three vertices" in output,
              f"{rules}: a Beauty-triangulated Suzanne applies, with a warning about its doubled faces")
        support.remove(obj)


# --- the active object, errors, undo --------------------------------------------------------------------------------

def active_object_only():
    first, second = uv_cube("First"), uv_cube("Second")
    support.select_only(first, second)
    result = bpy.ops.object.loop_subdivision_apply(levels=1)
    check(result == {'FINISHED'} and len(first.data.polygons) == 48 and len(second.data.polygons) == 12,
          "Apply acts on the active object only, as Blender's Apply does")
    support.remove(first)
    support.remove(second)


def snapshot(obj):
    mesh = obj.data
    return mesh, support.positions(mesh).copy(), len(mesh.polygons), len(mesh.edges)


def unchanged(obj, before):
    mesh, positions, faces, edges = before
    return (obj.data == mesh and np.array_equal(support.positions(mesh), positions, equal_nan=True)
            and len(mesh.polygons) == faces and len(mesh.edges) == edges)


def expect_error(obj, what, needle, **arguments):
    before = snapshot(obj)
    meshes = len(bpy.data.meshes)
    support.select_only(obj)
    try:
        bpy.ops.object.loop_subdivision_apply(**arguments)
        message = ""
    except RuntimeError as error:
        message = str(error)
    check(needle in message, f"{what}: an error report ({message.strip() or 'none'})")
    check(unchanged(obj, before) and len(bpy.data.meshes) == meshes, f"{what}: the mesh is left untouched")


def bad_meshes():
    obj = uv_cube("NotANumber")
    obj.data.vertices[3].co.x = float("nan")
    expect_error(obj, "a non-finite coordinate", "non-finite", levels=1)
    support.remove(obj)

    # Values other than positions are named by what holds them and where the Spreadsheet shows them.
    obj = uv_cube("BadUV")
    obj.data.uv_layers["UVMap"].data[5].uv = (float("nan"), 0.5)
    expect_error(obj, "a UV corner that is not a number",
                 'BadUV: UV map "UVMap" has a non-finite value at corner 5 (1 such corner)', levels=1)
    support.remove(obj)

    obj = uv_cube("BadAttribute")
    wetness = obj.data.attributes.new("wetness", 'FLOAT', 'POINT')
    wetness.data[2].value = float("inf")
    expect_error(obj, "an attribute value that is not finite",
                 'BadAttribute: attribute "wetness" has a non-finite value at vertex 2 (1 such vertex)', levels=1)
    support.remove(obj)

    obj = uv_cube("BadCorners")
    shade = obj.data.attributes.new("shade", 'FLOAT_COLOR', 'CORNER')
    shade.data[7].color = (0.5, float("nan"), 0.5, 1.0)
    shade.data[9].color = (float("nan"), 0.5, 0.5, 1.0)
    expect_error(obj, "corner values that are not finite",
                 'BadCorners: attribute "shade" has a non-finite value at corner 7 (2 such corners)', levels=1)
    support.remove(obj)

    # Adaptive Subdivision interpolates attributes itself: they pass the core's checks all the same.
    obj = uv_cube("BadAdaptive")
    wetness = obj.data.attributes.new("wetness", 'FLOAT', 'POINT')
    wetness.data[4].value = float("nan")
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    bpy.context.scene.collection.objects.link(camera)
    camera.location = (0.0, -8.0, 0.0)
    camera.rotation_euler = (math.pi / 2, 0.0, 0.0)
    bpy.context.scene.camera = camera
    expect_error(obj, "an attribute value that is not finite, with Adaptive Subdivision",
                 'BadAdaptive: attribute "wetness" has a non-finite value at vertex 4 (1 such vertex)',
                 use_adaptive=True)
    bpy.data.objects.remove(camera)
    support.remove(obj)

    obj = uv_cube("Infinite")
    obj.data.vertices[3].co.x = 3.4028235e38  # what Blender stores for an infinite coordinate typed in
    expect_error(obj, "a coordinate whose refinement would overflow", "too large to refine", levels=1)
    support.remove(obj)

    mesh = bpy.data.meshes.new("Degenerate")
    mesh.from_pydata([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0)], [], [(0, 1, 2), (1, 3, 2)])
    mesh.loops[5].vertex_index = 1  # face 1 becomes (1, 3, 1), as a broken import can leave it
    obj = bpy.data.objects.new("Degenerate", mesh)
    bpy.context.scene.collection.objects.link(obj)
    expect_error(obj, "a face repeating a vertex", "repeats a vertex", levels=1)
    support.remove(obj)

    obj = uv_cube("Shared")
    user = bpy.data.objects.new("OtherUser", obj.data)
    bpy.context.scene.collection.objects.link(user)
    expect_error(obj, "multi-user mesh data", "multi-user", levels=1)
    bpy.data.objects.remove(user)
    support.remove(obj)

    obj = uv_cube("Keyed")
    obj.shape_key_add(name="Basis")
    expect_error(obj, "a mesh with shape keys", "shape keys", levels=1)
    support.remove(obj)

    # 3,968 triangles: 260M at level 8, past the memory of any machine here (the message names both amounts).
    obj = support.object_from_bmesh("TooFine", support.uv_sphere(64, 32))
    expect_error(obj, "a level past the memory left", "Level 8 needs about", levels=8)
    support.remove(obj)

    obj = uv_cube("NoCone")
    obj.loop_subdivision.cone_group = "Missing"
    expect_error(obj, "a missing cone group", "does not exist", levels=1, rules='HOPPE94')
    support.remove(obj)


def undo_restores():
    """Undo in background mode works on Blender 3.4.1 once a first step exists: an operator called from Python pushes
    its own undo step (bl_options UNDO) only when asked to, with the positional undo flag, as a click in the UI
    would."""
    obj = uv_cube("Undo")
    before = support.positions(obj.data).copy()
    faces = len(obj.data.polygons)
    bpy.ops.ed.undo_push(message="before apply")
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_apply('EXEC_DEFAULT', True, levels=2)
    applied = len(bpy.data.objects["Undo"].data.polygons)
    bpy.ops.ed.undo()
    obj = bpy.data.objects["Undo"]
    check(applied == faces * 16 and len(obj.data.polygons) == faces
          and np.array_equal(support.positions(obj.data), before),
          f"undo restores the original mesh ({applied} faces after apply, {len(obj.data.polygons)} after undo)")
    support.remove(obj)


support.clear_scene()
faces_and_shading()
uv_seams(triangulate=True)
uv_seams(triangulate=False)
vertex_channels('OPENSUBDIV')
vertex_channels('HOPPE94')
creases_written()
loose_geometry()
other_attributes()
triangulated_suzanne()
active_object_only()
bad_meshes()
undo_restores()
addon.unregister()
check.finish()
