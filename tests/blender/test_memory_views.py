"""Views of Blender's memory (addon/blender/memory_views.py) against Blender's own accessors.

The same cage (quads and triangles, edge and vertex creases, seam and sharp marks, a UV map, flat and smooth faces),
applied and shown live, with views and with every array moved through Blender's accessors (memory_views.enabled
off): the meshes must be identical, array for array, read back through Blender's accessors. Each version must use the
views where they pay (else the speed-up is silently gone), and a view whose values differ from the accessor's must be
refused.
"""
import ctypes
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
blender_access = support.blender_access(addon)
views = addon.blender.memory_views
check = support.Check("test_memory_views")


def cage(name):
    """A cube cut 2x2 per side, half its faces triangulated, with every kind of data the views move."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=1, use_grid_fill=True)
    bm.faces.ensure_lookup_table()
    bmesh.ops.triangulate(bm, faces=bm.faces[:][::2])
    obj = support.object_from_bmesh(name, bm, triangulate=False)
    mesh = obj.data
    creased = np.arange(0, len(mesh.edges), 5)
    support.set_edge_creases(mesh, creased, 0.7, blender_access)
    corners = np.zeros(len(mesh.vertices), dtype=np.float32)
    corners[:3] = 1.0
    blender_access.write_vertex_creases(mesh, corners)
    for index in range(0, len(mesh.edges), 7):
        mesh.edges[index].use_seam = True
    for index in range(3, len(mesh.edges), 11):
        mesh.edges[index].use_edge_sharp = True
    for face in mesh.polygons:
        face.use_smooth = face.index % 3 != 0
    mesh.update()
    return obj


def accessor_arrays(mesh):
    """Everything the views could have touched, read through Blender's accessors alone."""
    enabled, views.enabled = views.enabled, False
    try:
        read = support.read_array
        arrays = {
            "positions": read(mesh.vertices, "co", 3),
            "edges": read(mesh.edges, "vertices", 2, np.int32),
            "corner vertices": read(mesh.loops, "vertex_index", dtype=np.int32),
            "corner edges": read(mesh.loops, "edge_index", dtype=np.int32),
            "face starts": read(mesh.polygons, "loop_start", dtype=np.int32),
            "face sizes": read(mesh.polygons, "loop_total", dtype=np.int32),
            "seams": read(mesh.edges, "use_seam", dtype=bool),
            "sharp edges": read(mesh.edges, "use_edge_sharp", dtype=bool),
            "smooth faces": read(mesh.polygons, "use_smooth", dtype=bool),
            "edge creases": blender_access.read_edge_creases(mesh),
            "vertex creases": blender_access.read_vertex_creases(mesh),
            "corner normals": blender_access.read_corner_normals(mesh),
        }
        for layer in mesh.uv_layers:
            arrays[f"UV map {layer.name}"] = read(layer.data, "uv", 2)
        return arrays
    finally:
        views.enabled = enabled


def applied_and_live(enabled):
    """(the applied mesh's arrays, the live entry's result's arrays), with the views on or off."""
    views.enabled = enabled
    try:
        applied = cage("Applied")
        result = support.apply_loop(applied, levels=2, use_limit_surface=True)
        check(result == {'FINISHED'}, f"views {'on' if enabled else 'off'}: Apply finishes")
        live = cage("Live")
        support.select_only(live)
        bpy.ops.object.loop_subdivision_add(levels=2)
        helper = addon.blender.stack.modifier_input(addon.blender.stack.entry(live), "Result")
        return accessor_arrays(applied.data), accessor_arrays(helper.data)
    finally:
        views.enabled = True
        support.clear_scene()


def test_same_meshes_both_ways():
    made = []
    block = views._block

    def counted_block(*arguments):
        view = block(*arguments)
        made.append(view is not None)
        return view

    views._block = counted_block
    try:
        with_views = applied_and_live(True)
    finally:
        views._block = block
    check(any(made), f"{bpy.app.version_string}: the add-on reads or writes through views of Blender's memory "
                     f"({sum(made)} of {len(made)} asked for)")
    without_views = applied_and_live(False)
    for kind, ours, theirs in zip(("Apply", "the live entry"), with_views, without_views):
        check(ours.keys() == theirs.keys(), f"{kind}: the same layers both ways")
        for name in ours:
            check(ours[name].shape == theirs[name].shape and np.array_equal(ours[name], theirs[name]),
                  f"{kind}: {name} identical with views and with Blender's accessors ({len(ours[name])} rows)")


def test_refused_layouts():
    obj = cage("Refused")
    mesh = obj.data
    positions = mesh.attributes.get("position")
    if positions is not None and bpy.app.version >= (4, 0, 0):
        check(views.attribute_array(positions, len(mesh.vertices), 3, ctypes.c_float) is not None,
              "the positions' attribute is viewed as floats")
        check(views.attribute_array(positions, len(mesh.vertices), 3, ctypes.c_int32) is None,
              "viewed as integers it reads other values than Blender's accessor: refused")
    else:
        fields = views._STRUCT_FIELDS
        check(views.struct_field(mesh.loops, "vertex_index") is not None, "3.4: the corners' vertices are viewed")
        views._STRUCT_FIELDS = {**fields, ("MeshLoop", "vertex_index"): fields[("MeshLoop", "edge_index")]}
        try:
            check(views.struct_field(mesh.loops, "vertex_index") is None,
                  "a field at the wrong place reads other values than Blender's accessor: refused")
        finally:
            views._STRUCT_FIELDS = fields
    views.enabled = False
    try:
        check(views.struct_field(mesh.loops, "vertex_index") is None and views.face_offsets(mesh.polygons) is None
              and views.attribute_array(positions, len(mesh.vertices), 3, ctypes.c_float) is None,
              "with views off no view is made")
    finally:
        views.enabled = True
    support.clear_scene()


test_same_meshes_both_ways()
test_refused_layouts()
check.finish()
