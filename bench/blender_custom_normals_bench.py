"""What writing custom normals costs in this Blender, per update of a result the size of a level-1 subdivision of the
100,352-triangle grid (a smooth-shaded, triangulated grid of 401,408 triangles, 1,204,224 corners): tangent space
per corner (Mesh.normals_split_custom_set) and per vertex (normals_split_custom_set_from_vertices), and from 4.5
free normals (the float vector attribute "custom_normal") on the point and the corner domain, each written into a
mesh that already has that storage, as the live entry does. Prints, best of 3: the write alone, and the write with
the evaluation and the corner normals read back (what a draw needs); and how far the normals read back are from
those written (tangent space stores them as 16-bit integers in each corner's normal space).

    blender --background --factory-startup --python bench/blender_custom_normals_bench.py
    build/bpy-5.2/bin/python tests/blender/run_in_bpy.py bench/blender_custom_normals_bench.py
"""
import importlib
import os
import sys
import time

import bmesh
import bpy
import numpy as np

# The add-on's shading, as each version keeps normals (addon/blender/shading.py), from the checkout's package.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
shading = importlib.import_module("addon.blender.shading")

bm = bmesh.new()
bmesh.ops.create_grid(bm, x_segments=448, y_segments=448, size=1.0)
bmesh.ops.triangulate(bm, faces=bm.faces[:])
mesh = bpy.data.meshes.new("Grid")
bm.to_mesh(mesh)
bm.free()
mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
shading.shade_sharp_edges(mesh)  # up to 4.0 custom normals show only with Auto Smooth
obj = bpy.data.objects.new("Grid", mesh)
bpy.context.scene.collection.objects.link(obj)
num_vertices, num_corners = len(mesh.vertices), len(mesh.loops)
# Unit normals leaning at most 30 degrees off the grid's: what a gently curved surface gives.
random = np.random.default_rng(1)
vertex_normals = random.normal(size=(num_vertices, 3)).astype(np.float32) * 0.3
vertex_normals[:, 2] = 1.0
vertex_normals /= np.linalg.norm(vertex_normals, axis=1, keepdims=True)
corner_vertices = np.empty(num_corners, dtype=np.int32)
mesh.loops.foreach_get("vertex_index", corner_vertices)
corner_normals = np.ascontiguousarray(vertex_normals[corner_vertices])


def shown_normals():
    """The evaluated mesh's corner normals (shading.read_corner_normals)."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    depsgraph.update()
    return shading.read_corner_normals(obj.evaluated_get(depsgraph).data)


def best_ms(function, repeat=3):
    samples = []
    for _ in range(repeat):
        started = time.perf_counter()
        function()
        samples.append(time.perf_counter() - started)
    return 1e3 * min(samples)


def row(name, write):
    write()
    mesh.update()
    error = np.abs(shown_normals() - corner_normals).max()

    def update():
        write()
        mesh.update()
        shown_normals()
    print(f"normals  {name:<28} write {best_ms(write):7.1f} ms   write, evaluate, read back {best_ms(update):7.1f} ms"
          f"   largest difference {error:.1e}")


def free(domain, values):
    """Writes values into a free "custom_normal" on domain, made once (the tangent-space normals cleared first)."""
    existing = mesh.attributes.get("custom_normal")
    if existing is not None:
        mesh.attributes.remove(existing)
    attribute = mesh.attributes.new("custom_normal", 'FLOAT_VECTOR', domain)
    return lambda: attribute.data.foreach_set("vector", values.ravel())


print(f"Blender {bpy.app.version_string}: {num_corners:,} corners, {num_vertices:,} vertices")
row("tangent space, per corner", lambda: mesh.normals_split_custom_set(corner_normals))
row("tangent space, per vertex", lambda: mesh.normals_split_custom_set_from_vertices(vertex_normals))
if shading.HAS_FREE_NORMALS:
    row("free, point domain", free('POINT', vertex_normals))
    row("free, corner domain", free('CORNER', corner_normals))
