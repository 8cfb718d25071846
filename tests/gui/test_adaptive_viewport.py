"""Adaptive Subdivision in Blender's interface (Debian's Blender 3.4.1 under Xvfb): the viewport's result follows the
3D Viewport's view, not the scene camera, once the view has stopped moving, and a render still cuts for the camera.

Run as ctest's gui.test_adaptive_viewport: `xvfb-run blender --factory-startup --python THIS -- --addon-dir DIR`. The
steps run from a timer, as an artist's actions would arrive between redraws; the process ends with the checks' exit
code.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
import bpy  # noqa: E402
from mathutils import Quaternion  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_adaptive_viewport")
SETTLE_SECONDS = 1.5  # the watcher reads the view 4 times a second and cuts once it is still


def region_3d():
    for area in bpy.context.window_manager.windows[0].screen.areas:
        if area.type == 'VIEW_3D':
            return area.spaces.active.region_3d
    raise RuntimeError("no 3D Viewport")


def shown_triangles(obj):
    return len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)


def steps():
    """Each step yields the seconds to wait before the next."""
    for obj in list(bpy.data.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    obj = support.object_from_bmesh("Sphere", support.icosphere())
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=8.0)
    view = region_3d()
    view.view_perspective = 'PERSP'
    view.view_distance = 30.0
    yield SETTLE_SECONDS
    far = shown_triangles(obj)
    builds = addon.live.engine.cache_of(obj).plan_builds
    view.view_distance = 4.0
    yield 0.05  # one read of the watcher at most: the view is still moving
    moving = shown_triangles(obj)
    yield SETTLE_SECONDS
    near = shown_triangles(obj)
    check(moving == far, f"while the view moves the last cut stays ({moving} triangles)")
    check(near > 4 * far and addon.live.engine.cache_of(obj).plan_builds == builds + 1,
          f"once the view is still, the result is cut for it: {near} triangles from 4 units, {far} from 30")
    yield SETTLE_SECONDS
    check(addon.live.engine.cache_of(obj).plan_builds == builds + 1, "a still view is cut once")
    # Rolling the view about its axis changes no edge's depth or length on screen: the rates stay, and so does the
    # result.
    view.view_rotation = view.view_rotation @ Quaternion((0.0, 0.0, 1.0), 0.3)
    yield SETTLE_SECONDS
    check(addon.live.engine.cache_of(obj).plan_builds == builds + 1 and shown_triangles(obj) == near,
          "a view change that changes no rate (a roll) cuts nothing again")
    scene = bpy.context.scene
    scene.camera.location = (0.0, -60.0, 0.0)
    scene.camera.rotation_euler = (1.5707964, 0.0, 0.0)
    scene.render.resolution_percentage = 25
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    obj.loop_subdivision.render_dicing_rate = 8.0
    seen = []

    def during_render(*_):
        helper = addon.blender.stack.helper_of(obj, addon.blender.stack.entry(obj), create=False)
        seen.append(len(helper.data.polygons))

    bpy.app.handlers.render_post.append(during_render)
    bpy.ops.render.render()
    bpy.app.handlers.render_post.remove(during_render)
    yield SETTLE_SECONDS
    check(seen and seen[0] < near, f"a render cuts for the scene camera, 60 units away: {seen[0] if seen else None} "
                                   f"triangles")
    check(shown_triangles(obj) == near, f"after the render the viewport shows its own cut again "
                                        f"({shown_triangles(obj)})")


support.run_in_interface(steps(), check)
