"""Too many levels never get Blender killed: a second Blender runs in a memory cgroup of 2 GiB (the kernel's OOM
killer ends a process there, as on a desktop out of memory or in a render farm's slot) and asks a 20,480-triangle
icosphere for level 5 (21 million triangles, some 15 GB) at every entry point: Levels Viewport, Render levels and a
render, the add-on's Apply, and adding an entry; and Adaptive Subdivision for 64 segments an edge (84 million
triangles). Each is refused with a message that says what it needs and what is free, the input shows meanwhile, and
the process lives to the end.

The control: the same Blender with the add-on's memory check taken out (its estimate of the memory left made
unknown) and asked for level 5 is killed, so the cgroup is a real limit and the check is what saves Blender.
Skipped (exit code 77) where no memory cgroup can be made.
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon(register=False)
check = support.Check("test_memory_limit")
ADDON_DIR = os.path.dirname(addon.__file__)
LIMIT = 2 << 30

SCRIPT = f"""
import sys, bpy
sys.path.insert(0, {os.path.dirname(ADDON_DIR)!r})
import {os.path.basename(ADDON_DIR)} as addon
addon.register()
live = addon.live.engine

def faces(obj):
    return len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)

def say(*words):
    print(*words, flush=True)

bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=6)
obj = bpy.context.object
cage = len(obj.data.polygons)
"""

REFUSALS = SCRIPT + """
assert bpy.ops.object.loop_subdivision_add(levels=1) == {'FINISHED'}
say("ADDED", faces(obj) == 4 * cage)
obj.loop_subdivision.levels = 5
say("VIEWPORT", faces(obj) == cage, "|", live.cache_of(obj).error)
obj.loop_subdivision.levels = 1
say("BACK", faces(obj) == 4 * cage)

scene = bpy.context.scene
scene.render.engine = 'CYCLES'
scene.cycles.samples = 1
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = 8
bpy.ops.object.camera_add(location=(0, -6, 0), rotation=(1.5708, 0, 0))
scene.camera = bpy.context.object
bpy.context.view_layer.objects.active = obj
obj.loop_subdivision.render_levels = 5
say("RENDERING")
bpy.ops.render.render()
say("RENDERED")

try:
    bpy.ops.object.loop_subdivision_apply(levels=5)
    say("APPLY", "applied")
except RuntimeError as error:
    say("APPLY", len(obj.data.polygons) == cage, "|", str(error).strip())

bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=6, location=(3, 0, 0))
other = bpy.context.object
bpy.ops.object.loop_subdivision_add(levels=5)
say("ADD", faces(other) == cage, "|", live.cache_of(other).error)

scene.render.resolution_x = scene.render.resolution_y = 2000
bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=6, location=(0, 0, 0))
near = bpy.context.object
bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=0.1, max_rate=64)
say("ADAPTIVE", faces(near) == cage, "|", live.cache_of(near).error)
say("SURVIVED")
"""

UNCHECKED = SCRIPT + """
addon.model.memory.available_bytes = lambda root="/": None
say("ASKING")
bpy.ops.object.loop_subdivision_add(levels=5)
say("SURVIVED")
"""


def line(output, marker):
    return next((text for text in output.splitlines() if text.startswith(marker + " ")), "")


with support.memory_cgroup(LIMIT) as cgroup, tempfile.TemporaryDirectory() as folder:
    if cgroup is None:
        print("test_memory_limit: skipped, this machine lets no memory cgroup be made")
        sys.exit(77)
    support.clear_scene()
    blend = os.path.join(folder, "empty.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)

    code, output = support.run_blender(blend, REFUSALS, cgroup=cgroup, timeout=600)
    need = "Level 5 needs about"
    if not check(code == 0 and "SURVIVED" in output,
                 f"Blender in a 2 GiB cgroup lives through every request (exit {code})"):
        print(output[-4000:])
    check(line(output, "ADDED").startswith("ADDED True"), "level 1 fits and is made")
    viewport = line(output, "VIEWPORT")
    check(viewport.startswith("VIEWPORT True") and need in viewport and "are free" in viewport,
          f"Levels Viewport 5: refused, the input shown, the panel says why ({viewport})")
    check(line(output, "BACK").startswith("BACK True"), "back at level 1, the result is made again")
    rendering = output.split("RENDERING", 1)[-1]
    check("RENDERED" in rendering and f"Loop Subdivision: Icosphere: {need}" in rendering,
          "Render levels 5: the render goes on with the input, the console says why")
    apply_ = line(output, "APPLY")
    check(apply_.startswith("APPLY True") and need in apply_,
          f"Apply at level 5: refused with the message, the mesh untouched ({apply_})")
    added = line(output, "ADD")
    check(added.startswith("ADD True") and need in added,
          f"adding an entry at level 5: refused, the input shown ({added})")

    adaptive = line(output, "ADAPTIVE")
    check(adaptive.startswith("ADAPTIVE True") and "Adaptive Subdivision at 0.1 px" in adaptive
          and "are free" in adaptive,
          f"Adaptive Subdivision at 0.1 px, 64 segments an edge: refused, the input shown ({adaptive})")

    code, output = support.run_blender(blend, UNCHECKED, cgroup=cgroup, timeout=600)
    check("ASKING" in output and "SURVIVED" not in output and code != 0,
          f"control: without the check, level 5 gets the same Blender killed (exit {code})")
check.finish()
