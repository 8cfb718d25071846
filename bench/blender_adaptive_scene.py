"""Adaptive Subdivision against uniform levels on one scene: a ground plane and Suzanne, both with a Loop Subdivision
entry, rendered by Cycles from a camera that moves towards them. For each way of cutting (Render levels 1-4, Adaptive
Subdivision by length at 2 and 1 px, by deviation at 0.1 px) and each frame: the triangles rendered, the add-on's
time to make them (the render's own evaluation, before each frame) and the render's time; a picture of every frame.

Usage: blender --background --factory-startup --python bench/blender_adaptive_scene.py -- --addon-dir DIR --out DIR
           [--frames N] [--resolution W H] [--samples N]
(scripts/bench_blender.sh --adaptive-scene runs it and joins the pictures side by side.)
"""
import argparse
import math
import os
import sys
import time

import bpy
import bmesh

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender"))
import blender_test_support as support  # noqa: E402

addon = support.load_addon()


def arguments():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--frames", type=int, default=3)
    parser.add_argument("--resolution", type=int, nargs=2, default=(640, 360))
    parser.add_argument("--samples", type=int, default=16)
    return parser.parse_known_args(sys.argv[sys.argv.index("--") + 1:])[0]


def build_scene(frames):
    support.clear_scene()
    scene = bpy.context.scene
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=12, y_segments=12, size=20.0)
    ground = support.object_from_bmesh("Ground", bm)
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 1.2), rotation=(0.0, 0.0, 0.0))
    suzanne = bpy.context.object
    suzanne.name = "Suzanne"
    suzanne.rotation_euler = (math.radians(-10), 0.0, 0.0)
    for obj in (ground, suzanne):
        support.shade_smooth(obj)
        support.select_only(obj)
        bpy.ops.object.loop_subdivision_add(rules='OPENSUBDIV', levels=1)
    sun = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", 'SUN'))
    sun.rotation_euler = (math.radians(50), 0.0, math.radians(30))
    scene.collection.objects.link(sun)
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    target = camera.constraints.new('TRACK_TO')
    target.target = suzanne
    target.track_axis, target.up_axis = 'TRACK_NEGATIVE_Z', 'UP_Y'
    # From 14 units away and low over the ground to 5 units from Suzanne's face.
    for frame, (y, z) in ((1, (-14.0, 2.4)), (frames, (-5.0, 1.7))):
        camera.location = (1.0, y, z)
        camera.keyframe_insert("location", frame=frame)
    scene.frame_start, scene.frame_end = 1, frames
    ground.data.materials.append(checker_material())
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.color = (0.4, 0.45, 0.5)
    return scene, (ground, suzanne)


def checker_material():
    """A checker of 2-unit squares in object space: the ground's extent and perspective show in the pictures."""
    material = bpy.data.materials.new("Checker")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 0.5
    coordinates = nodes.new("ShaderNodeTexCoord")
    material.node_tree.links.new(coordinates.outputs["Object"], checker.inputs["Vector"])
    material.node_tree.links.new(checker.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    return material


# How each row cuts: Render levels, or Adaptive Subdivision at a dicing rate in pixels by a measure.
WAYS = [("levels", level, None) for level in (1, 2, 3, 4)] + [
    ("adaptive", 2.0, 'LENGTH'), ("adaptive", 1.0, 'LENGTH'), ("adaptive", 0.1, 'DEVIATION')]


def way_name(way):
    kind, value, measure = way
    return f"levels-{value}" if kind == "levels" else f"adaptive-{measure.lower()}-{value:g}px"


def set_cutting(objects, way):
    kind, value, measure = way
    for obj in objects:
        settings = obj.loop_subdivision
        if kind == "levels":
            settings.use_adaptive, settings.render_levels = False, value
        else:
            settings.use_adaptive, settings.render_dicing_rate, settings.dicing_measure = True, value, measure


def main():
    args = arguments()
    os.makedirs(args.out, exist_ok=True)
    scene, objects = build_scene(args.frames)
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = 'PNG'

    evaluation = []
    render_levels = addon.live.render._render_levels

    def timed_render_levels():
        start = time.perf_counter()
        render_levels()
        evaluation.append(time.perf_counter() - start)

    addon.live.render._render_levels = timed_render_levels
    triangles = []

    def count(*_):
        stack = addon.blender.stack
        triangles.append(sum(len(stack.helper_of(obj, stack.entry(obj), create=False).data.polygons)
                             for obj in objects))

    bpy.app.handlers.render_post.append(count)
    print(f"Blender {bpy.app.version_string}, {args.resolution[0]} x {args.resolution[1]} px, Cycles "
          f"{args.samples} samples, {os.cpu_count()} threads")
    print("scene | way | frame | triangles | evaluation s | render s")
    for way in WAYS:
        set_cutting(objects, way)
        name = way_name(way)
        for frame in range(1, args.frames + 1):
            scene.frame_set(frame)
            evaluation.clear()
            triangles.clear()
            scene.render.filepath = os.path.join(args.out, f"{name}-frame{frame}.png")
            start = time.perf_counter()
            bpy.ops.render.render(write_still=True)
            total = time.perf_counter() - start
            made = sum(evaluation)
            print(f"scene | {name} | {frame} | {triangles[0] if triangles else 0} | {made:.3f} | "
                  f"{total - made:.2f}")
    addon.live.render._render_levels = render_levels


main()
