"""Loop Subdivision against Blender's Subdivision Surface in one Blender run: Apply, edits of every cage vertex, and
animation playback. Prints medians; run with scripts/bench_blender.sh (or blender -b --factory-startup --python this
-- --addon-dir addon [--repeat N] [--only NAME]).

- Apply: the add-on's operator vs Blender's modifier_apply of Subdivision Surface (Catmull-Clark of the same
  triangles), in rounds that take turns (apply_rows), each with its default, the limit surface on (the add-on then
  also writes the limit normals as custom normals), and with the limit surface off (refinement only), on a 200x200
  grid (80,000 triangles) at level 2 and a 20,480-triangle icosphere at level 3, without and with a UV map
  (Blender's icosphere unwrap, seams included); times per output vertex too, since Catmull-Clark of triangles makes
  more vertices than Loop. Ratios compare like with like (limit on with limit on). And the 200x200 grid left as
  quads, as artists model it: Subdivision Surface gets the quads, the add-on triangulates them itself (Blender's
  tessellation; the same vertex count at level 2 on both sides); the same with seams marked along its middle lines,
  which both carry onto the child edges.
- Edit: every cage vertex moves, then the evaluated mesh is asked for (what a viewport redraw waits on), on a
  100,352-triangle grid at level 1, limit surface on (both defaults) and off.
- Playback: frames per second of a Wave-deformed 20,480-triangle icosphere at level 2 (the Wave modifier, animated
  by time, above Loop Subdivision or Subdivision Surface), stepping frames, limit surface on and off, and with a UV
  map; and of a Wave-deformed box of 20,172 triangles with its 12 edges creased (limit on), where the limit normals
  split along the creases.

With the limit surface, every edit and every frame of the add-on's result carries the exact limit normals, as Apply
writes them (docs/addon.md, Normals).
"""
import argparse
import os
import statistics
import sys
import time

import bpy
import bmesh
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender"))
import blender_test_support as support  # noqa: E402  (mesh and add-on helpers shared with the tests)

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--repeat", type=int, default=5)
parser.add_argument("--only", default="", help="run only the rows whose mesh name contains this")
args, _ = parser.parse_known_args(argv)
addon = support.load_addon()


def mesh_object(name, build, triangulate=True):
    """A cage shaded smooth, as artists shade what they subdivide: flat faces stay flat through both subdivisions,
    and with the limit surface only smooth ones get the limit normals. Triangulated, so that Subdivision Surface sees
    the add-on's triangles, unless triangulate is False."""
    bm = bmesh.new()
    build(bm)
    return support.shade_smooth(support.object_from_bmesh(name, bm, triangulate))


def grid(cuts):
    return lambda bm: bmesh.ops.create_grid(bm, x_segments=cuts, y_segments=cuts, size=1.0)


def seamed_grid(cuts):
    """A grid cut for its UV map as artists cut one: seams along its two middle lines."""
    def build(bm):
        bmesh.ops.create_grid(bm, x_segments=cuts, y_segments=cuts, size=1.0)
        for edge in bm.edges:
            a, b = (vertex.co for vertex in edge.verts)
            edge.seam = any(abs(a[axis]) < 1e-6 and abs(b[axis]) < 1e-6 for axis in (0, 1))
    return build


def icosphere(subdivisions, uvs=False):
    def build(bm):
        if uvs:
            bm.loops.layers.uv.new("UVMap")
        bmesh.ops.create_icosphere(bm, subdivisions=subdivisions, radius=1.0, calc_uvs=uvs)
    return build


def creased_box(cuts):
    """A cube cut into (cuts + 1)^2 squares per side, triangulated by mesh_object, its 12 edges creased (1.0)."""
    def build(bm):
        bmesh.ops.create_cube(bm, size=2.0)
        bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=cuts, use_grid_fill=True)
        crease, _ = addon.blender.creases.bmesh_crease_layers(bm)
        for edge in bm.edges:
            a, b = (vertex.co for vertex in edge.verts)
            if all(sum(abs(abs(c) - 1.0) < 1e-6 for c in p) >= 2 for p in (a, b)) and \
                    sum(abs(x - y) > 1e-6 for x, y in zip(a, b)) == 1:
                edge[crease] = 1.0
    return build


def timed(function):
    started = time.perf_counter()
    function()
    return time.perf_counter() - started


def median(samples):
    return statistics.median(samples)


def subsurf(obj, levels, use_limit_surface=True):
    modifier = obj.modifiers.new("Subdivision", 'SUBSURF')
    modifier.levels = modifier.render_levels = levels
    modifier.use_limit_surface = use_limit_surface
    return modifier


def apply_rows(name, build, levels, triangulate=True):
    def loop(use_limit_surface):
        def run(obj):
            return bpy.ops.object.loop_subdivision_apply(levels=levels, rules='OPENSUBDIV',
                                                         use_limit_surface=use_limit_surface)
        return run

    def blender(use_limit_surface):
        def run(obj):
            modifier = subsurf(obj, levels, use_limit_surface)
            with bpy.context.temp_override(object=obj, active_object=obj):
                bpy.ops.object.modifier_apply(modifier=modifier.name)
        return run

    kinds = (("Loop", loop(True)), ("Subdivision Surface", blender(True)),
             ("Loop, limit off", loop(False)), ("Subdivision Surface, limit off", blender(False)))
    samples = {kind: [] for kind, _ in kinds}
    vertices = {}
    # Rounds of one Apply of each kind after a round untimed, in the orders of a Williams square, so that each kind
    # follows each other kind equally often (but for the turns between rounds): an Apply's time depends on what the
    # Apply before it left in Blender's allocator (memory to reuse, or fresh pages the kernel must map and clear;
    # docs/benchmark.md), and the first in a process pays most. A slow spell of the host falls on all kinds alike.
    orders = [[(first + step) % len(kinds) for step in (0, 1, 3, 2)] for first in range(len(kinds))]
    for round_index in range(-1, args.repeat):
        for kind, apply in (kinds[k] for k in orders[max(round_index, 0) % len(orders)]):
            obj = mesh_object(name, build, triangulate)
            seconds = timed(lambda: apply(obj))
            if round_index >= 0:
                samples[kind].append(seconds)
            vertices[kind] = len(obj.data.vertices)
            support.clear_scene()
    rows = {kind: (median(samples[kind]), vertices[kind]) for kind, _ in kinds}
    for kind, (seconds, vertices) in rows.items():
        ratio = ""
        if not kind.startswith("Loop"):
            ours, ours_vertices = rows["Loop, limit off" if kind.endswith("limit off") else "Loop"]
            ratio = (f"   Loop/this: time {ours / seconds:4.2f}, "
                     f"per vertex {ours / ours_vertices / (seconds / vertices):4.2f}")
        print(f"apply  {name:<28} level {levels}  {kind:<31} {seconds * 1e3:8.1f} ms {vertices:>9,} vertices "
              f"{seconds / vertices * 1e9:6.0f} ns/vertex{ratio}")


def edit_rows(name, build, levels, use_limit_surface=True):
    results = {}
    for kind in ("Loop", "Subdivision Surface"):
        obj = mesh_object(name, build)
        if kind == "Loop":
            bpy.ops.object.loop_subdivision_add(levels=levels, rules='OPENSUBDIV',
                                                use_limit_surface=use_limit_surface)
        else:
            subsurf(obj, levels, use_limit_surface)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        co = np.empty(len(obj.data.vertices) * 3, np.float32)
        obj.data.vertices.foreach_get("co", co)
        samples = []
        for step in range(args.repeat + 1):
            co[2::3] += 0.001

            def edit():
                obj.data.vertices.foreach_set("co", co)
                obj.data.update()
                obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.vertices[0].co  # noqa: B018

            seconds = timed(edit)
            if step:  # the first evaluation builds the plan / Blender's subdivision topology
                samples.append(seconds)
        results[kind] = median(samples), len(obj.evaluated_get(depsgraph).data.vertices)
        support.clear_scene()
    (ours, n_ours), (theirs, n_theirs) = results["Loop"], results["Subdivision Surface"]
    limit = "limit on " if use_limit_surface else "limit off"
    print(f"edit   {name:<28} level {levels}, {limit}: Loop {ours * 1e3:8.1f} ms ({n_ours:,} vertices)   "
          f"Subdivision Surface {theirs * 1e3:8.1f} ms ({n_theirs:,} vertices)   time ratio {ours / theirs:4.2f}")


def shown_positions(obj):
    """The evaluated mesh's positions, what the viewport draws each frame. Blender 4.x as a Python module evaluates
    no depsgraph on frame_set by itself, and Subdivision Surface leaves its result to be made when first read (for
    GPU subdivision): reading it makes both sides do a frame's whole work, in every version."""
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    positions = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", positions)
    return positions


def playback_rows(name, build, levels, frames=24, use_limit_surface=True):
    results = {}
    scene = bpy.context.scene
    for kind in ("Loop", "Subdivision Surface"):
        obj = mesh_object(name, build)
        wave = obj.modifiers.new("Wave", 'WAVE')
        wave.height = 0.1
        if kind == "Loop":
            bpy.ops.object.loop_subdivision_add(levels=levels, rules='OPENSUBDIV',
                                                use_limit_surface=use_limit_surface)
        else:
            subsurf(obj, levels, use_limit_surface)
        scene.frame_set(1)
        samples = []
        for _ in range(args.repeat):
            started = time.perf_counter()
            for frame in range(2, 2 + frames):
                scene.frame_set(frame)
                shown_positions(obj)
            samples.append(frames / (time.perf_counter() - started))
        results[kind] = median(samples)
        support.clear_scene()
    limit = "limit on " if use_limit_surface else "limit off"
    print(f"play   {name:<28} level {levels}, {limit}: Loop {results['Loop']:6.1f} fps   "
          f"Subdivision Surface {results['Subdivision Surface']:6.1f} fps")


support.clear_scene()
print(f"Blender {bpy.app.version_string}, medians of {args.repeat}")
rows = [
    (apply_rows, "grid 200x200 (80,000 tris)", grid(200), 2, {}),
    (apply_rows, "quad grid 200x200 (40,000 quads)", grid(200), 2, {"triangulate": False}),
    (apply_rows, "quad grid with seams 200x200", seamed_grid(200), 2, {"triangulate": False}),
    (apply_rows, "icosphere (20,480 tris)", icosphere(5), 3, {}),
    (apply_rows, "icosphere with UVs (20,480 tris)", icosphere(5, uvs=True), 3, {}),
    (edit_rows, "grid 224x224 (100,352 tris)", grid(224), 1, {}),
    (edit_rows, "grid 224x224 (100,352 tris)", grid(224), 1, {"use_limit_surface": False}),
    (playback_rows, "icosphere (20,480 tris)", icosphere(5), 2, {}),
    (playback_rows, "icosphere (20,480 tris)", icosphere(5), 2, {"use_limit_surface": False}),
    (playback_rows, "icosphere with UVs (20,480 tris)", icosphere(5, uvs=True), 2, {}),
    (playback_rows, "creased box (20,172 tris)", creased_box(40), 2, {}),
]
for row, name, build, levels, keywords in rows:
    if args.only in name:
        row(name, build, levels, **keywords)
