"""Edit Mode in Blender's interface: the time from moving every cage vertex to the redrawn window, Loop Subdivision
against Subdivision Surface (which Blender may evaluate on the GPU), on a 100,352-triangle grid at level 1.

Needs a display: scripts/bench_blender.sh --gui runs it under Xvfb (Mesa's software OpenGL). Prints medians.
"""
import os
import statistics
import sys
import time

import bpy
import bmesh

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender"))
import blender_test_support as support  # noqa: E402  (mesh and add-on helpers shared with the tests)

support.load_addon()
REPEAT = 7


def grid_object(name):
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=224, y_segments=224, size=1.0)
    return support.object_from_bmesh(name, bm)


def measure(kind):
    obj = grid_object(kind)
    if kind == "Loop":
        bpy.ops.object.loop_subdivision_add(levels=1, rules='OPENSUBDIV')
    else:
        obj.modifiers.new("Subdivision", 'SUBSURF').levels = 1
    bpy.ops.object.mode_set(mode='EDIT')
    edit = bmesh.from_edit_mesh(obj.data)
    samples = []
    for step in range(REPEAT + 1):
        for vertex in edit.verts:
            vertex.co.z += 0.001
        started = time.perf_counter()
        bmesh.update_edit_mesh(obj.data)
        bpy.ops.wm.redraw_timer(type='DRAW_WIN_SWAP', iterations=1)
        if step:  # the first builds the plan / Blender's subdivision topology
            samples.append(time.perf_counter() - started)
    bpy.ops.object.mode_set(mode='OBJECT')
    faces = len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)
    bpy.data.objects.remove(obj)
    return statistics.median(samples), faces


def run():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for area in bpy.context.screen.areas:
        if area.type == 'VIEW_3D':
            area.spaces[0].shading.type = 'SOLID'
    ours, ours_faces = measure("Loop")
    theirs, theirs_faces = measure("Subdivision Surface")
    gpu = bpy.context.preferences.system.use_gpu_subdivision
    print(f"gui-edit grid 224x224 (100,352 tris) level 1, median of {REPEAT}: Loop {ours * 1e3:.1f} ms "
          f"({ours_faces:,} faces)   Subdivision Surface {theirs * 1e3:.1f} ms ({theirs_faces:,} faces, GPU "
          f"subdivision {'on' if gpu else 'off'})   time ratio {ours / theirs:.2f}", flush=True)
    bpy.ops.wm.quit_blender()


bpy.app.timers.register(run, first_interval=1.0)
