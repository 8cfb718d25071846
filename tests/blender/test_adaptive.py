"""Adaptive Subdivision in Blender: each cage edge cut into as many segments as the camera needs, on the limit surface.

What an artist relies on: the option is off by default with Cycles' dicing rates; the result has no cracks; its
points lie on the limit surface; an edge gets the segments its length on screen asks for (worked out here by hand
from the camera's lens and the render's size, not by the core); the viewport and a render each use their dicing
rate, Apply the render's; Max Segments caps the rates; an entry with no camera to cut for says so and passes its
input through; the memory check's estimate of an update covers what Blender's memory grows by.
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bmesh  # noqa: E402
import bpy  # noqa: E402
import numpy as np  # noqa: E402
from mathutils.bvhtree import BVHTree  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_adaptive")
stack = addon.blender.stack


def core():
    from importlib import import_module
    return import_module(addon.__name__ + "._loopsub")


def top_camera(height, lens=20.0, resolution=1000, percentage=10):
    """A camera at (0, 0, height) looking down -z at the origin; the render resolution x resolution pixels at
    percentage. Returns its pixels per unit of length at depth 1 (the lens over the sensor's width, 36 mm, times the
    render's width in pixels)."""
    scene = bpy.context.scene
    camera = scene.camera
    if camera is None:
        camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
        scene.collection.objects.link(camera)
        scene.camera = camera
    camera.location = (0.0, 0.0, height)
    camera.rotation_euler = (0.0, 0.0, 0.0)
    camera.data.lens = lens
    camera.data.sensor_width = 36.0
    camera.data.sensor_fit = 'AUTO'
    scene.render.resolution_x = scene.render.resolution_y = resolution
    scene.render.resolution_percentage = percentage
    return lens / 36.0 * resolution * percentage / 100


def shown(obj):
    return obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data


def points_on_side(mesh):
    """How many vertices lie on the middle half of the side y = -1 of a 2 x 2 grid in the xy-plane cut 4 x 4 (its two
    middle edges, which the limit keeps straight: its rounded corners are an edge away)."""
    p = support.positions(mesh)
    return int(np.count_nonzero((np.abs(p[:, 1] + 1) < 1e-5) & (np.abs(p[:, 0]) <= 0.5 + 1e-5)))


def expected_rate(length, midpoint, height, pixels_per_unit, dicing_rate):
    """Cycles' dicing: an edge as if it faced the camera at (0, 0, height) straight ahead at its midpoint's distance,
    cut into segments of at most dicing_rate pixels."""
    distance = np.linalg.norm(np.subtract(midpoint, (0.0, 0.0, height)))
    return int(np.ceil(length * pixels_per_unit / distance / dicing_rate))


def defaults():
    """Off by default, so that a file behaves as before; the dicing rates Cycles defaults to."""
    obj = support.object_from_bmesh("Defaults", support.octahedron())
    bpy.ops.object.loop_subdivision_add()
    settings = obj.loop_subdivision
    check(not settings.use_adaptive and settings.dicing_rate == 8.0 and settings.render_dicing_rate == 1.0
          and settings.dicing_measure == 'LENGTH',
          "Adaptive Subdivision is off by default; Dicing Rate Viewport 8 px, Render 1 px, by length (Cycles')")
    support.remove(obj)


def rates_from_the_camera():
    """A 2 x 2 grid seen from above: the segments of its boundary edges are what their length on screen gives, at the
    viewport's dicing rate in the entry (background mode: the scene camera), at the render's in Apply; more for an
    object scaled 1.5 times (its transform counts); Max Segments caps them."""
    pixels_per_unit = top_camera(2.0)
    obj = support.object_from_bmesh("Grid", support.grid(cuts=4, size=2.0))
    length = 0.5
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=4.0)
    # The side's two middle edges, midpoints (-+0.25, -1, 0).
    viewport = expected_rate(length, (0.25, -1.0, 0.0), 2.0, pixels_per_unit, 4.0)
    check(points_on_side(shown(obj)) == 2 * viewport + 1,
          f"viewport: each boundary edge cut into {viewport} segments "
          f"({points_on_side(shown(obj)) - 1} / 2)")
    obj.scale = (1.5, 1.5, 1.5)  # its side y = -1.5 still in view
    bpy.context.view_layer.update()
    scaled = expected_rate(1.5 * length, (0.375, -1.5, 0.0), 2.0, pixels_per_unit, 4.0)
    check(points_on_side(shown(obj)) == 2 * scaled + 1,
          f"the object scaled by 1.5: {scaled} segments an edge ({points_on_side(shown(obj)) - 1} / 2)")
    obj.scale = (1.0, 1.0, 1.0)
    obj.loop_subdivision.max_rate = 3
    check(points_on_side(shown(obj)) == 2 * 3 + 1, "Max Segments 3: 3 segments an edge")
    obj.loop_subdivision.max_rate = 64
    obj.loop_subdivision.render_dicing_rate = 0.5
    render = expected_rate(length, (0.25, -1.0, 0.0), 2.0, pixels_per_unit, 0.5)
    result = support.apply_loop(obj)
    check(result == {'FINISHED'} and points_on_side(obj.data) == 2 * render + 1
          and stack.entry(obj) is None,
          f"Apply cuts at the Render dicing rate: {render} segments an edge "
          f"({points_on_side(obj.data) - 1} / 2) and removes the entry")
    support.remove(obj)


def edits_keep_the_cut():
    """Moving a vertex a little changes no rate: the result is updated in place on the same tessellation (its
    topology and rates kept), and equals what Apply makes of the edited mesh from the same camera and dicing rate."""
    top_camera(2.0)
    obj = support.object_from_bmesh("Edited", support.grid(cuts=4, size=2.0))
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=4.0, render_dicing_rate=4.0)
    cache = addon.live.engine.cache_of(obj)
    builds = cache.plan_builds
    before = support.positions(shown(obj))
    middle = int(np.argmin(np.linalg.norm(support.positions(obj.data), axis=1)))
    obj.data.vertices[middle].co.z += 0.01
    obj.data.update()
    after = support.positions(shown(obj))
    twin = support.copy_object(obj, "Edited twin")
    twin.modifiers.clear()
    support.apply_loop(twin)
    check(cache.plan_builds == builds and len(after) == len(before) and not np.array_equal(after, before)
          and np.array_equal(after, support.positions(twin.data)),
          "an edit that changes no rate updates the result in place, equal to Apply's")
    support.remove(twin)
    support.remove(obj)


def camera_moves_cut_anew():
    """The camera comes nearer: the entry cuts again (the last cut's work on the cage handed on), and the new cut
    equals what Apply makes from that camera, points and UVs."""
    def uvs(mesh):
        return support.read_array(mesh.uv_layers["UVMap"].data, "uv", 2)

    top_camera(2.0)
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_grid(bm, x_segments=4, y_segments=4, size=1.0, calc_uvs=True)
    obj = support.object_from_bmesh("Approached", bm)
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=4.0, render_dicing_rate=4.0)
    cache = addon.live.engine.cache_of(obj)
    builds, far = cache.plan_builds, len(shown(obj).polygons)
    top_camera(1.2)
    bpy.context.view_layer.update()
    near = shown(obj)
    near_faces, near_points, near_uvs = len(near.polygons), support.positions(near), uvs(near)
    twin = support.copy_object(obj, "Approached twin")
    twin.modifiers.clear()
    support.apply_loop(twin)
    check(cache.plan_builds == builds + 1 and near_faces > far and np.array_equal(near_uvs, uvs(twin.data))
          and np.array_equal(near_points, support.positions(twin.data)),
          f"a nearer camera cuts again ({far} -> {near_faces} triangles), equal to Apply's, UVs too")
    support.remove(twin)
    support.remove(obj)


def uvs_follow_uv_smooth():
    """UV maps on the adaptive path are refined as levels refine them, in every UV Smooth mode: with every edge cut
    into 2 segments (Max Segments 2 from a near camera), Apply's corners are level 1's with the limit surface, each
    corner's position with its UV (a UV sphere: a seam along a meridian, every pole triangle its own UVs)."""
    top_camera(3.0)
    modes = [item.identifier for item in bpy.types.SubsurfModifier.bl_rna.properties["uv_smooth"].enum_items]
    for mode in modes:
        bm = bmesh.new()
        bm.loops.layers.uv.new("UVMap")
        bmesh.ops.create_uvsphere(bm, u_segments=8, v_segments=6, radius=1.0, calc_uvs=True)
        obj = support.object_from_bmesh("UVs", bm)
        obj.loop_subdivision.max_rate = 2
        levels = support.copy_object(obj, "UVs levels")
        support.apply_loop(obj, use_adaptive=True, dicing_rate=0.5, uv_smooth=mode, rules='OPENSUBDIV')
        support.apply_loop(levels, levels=1, uv_smooth=mode, rules='OPENSUBDIV')

        def corners(mesh):
            loops = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
            return support.positions(mesh)[loops], support.read_array(mesh.uv_layers["UVMap"].data, "uv", 2)

        (points, uvs), (level_points, level_uvs) = corners(obj.data), corners(levels.data)
        # Each corner against level 1's corners at its place (a seam vertex has several, with different UVs).
        worst = max(np.abs(level_uvs[np.linalg.norm(level_points - point, axis=1) < 1e-5] - uv).max(axis=1).min()
                    for point, uv in zip(points, uvs))
        check(len(obj.data.polygons) == len(levels.data.polygons) and worst < 1e-5,
              f"UV Smooth {mode}: Adaptive at 2 segments an edge gives level 1's UV at every corner (within "
              f"{worst:.1e})")
        support.remove(levels)
        support.remove(obj)


def limit_surface_without_cracks():
    """A closed cage with creases, seen from a camera that makes rates differ from edge to edge: the result is closed
    (every edge between two faces, Euler characteristic 2: no crack), every point lies on the limit surface (a
    dense mesh of it, level 6 of the core's plan with the limit surface, verified against OpenSubdiv elsewhere) and
    its normals are the surface's; a nearer camera cuts finer."""
    top_camera(6.0)
    obj, _ = support.creased_cube(support.blender_access(addon), weight=1.0)
    obj.rotation_euler = (0.3, 0.2, 0.1)
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, rules='OPENSUBDIV', dicing_rate=2.0)
    support.shade_smooth(obj)
    mesh = shown(obj)
    counts = support.edge_face_counts(mesh)
    euler = len(mesh.vertices) - len(mesh.edges) + len(mesh.polygons)
    check(len(mesh.polygons) > 4 * 24 and (counts == 2).all() and euler == 2,
          f"closed: {len(mesh.polygons)} triangles, every edge between two faces, V - E + F = {euler}")
    cage = obj.data
    cage.calc_loop_triangles()
    triangles = support.read_array(cage.loop_triangles, "vertices", 3, np.int32)
    crease_edges = support.edges(cage)[addon.blender.creases.read_edge_creases(cage) > 0]
    plan = core().Plan(triangles, len(cage.vertices), 6, rules="opensubdiv", limit_surface=True,
                       crease_edges=np.ascontiguousarray(crease_edges, np.int32),
                       crease_sharpness=np.full(len(crease_edges), 10.0, np.float32))
    dense, _ = plan.evaluate_with_normals(support.positions(cage))
    tree = BVHTree.FromPolygons([tuple(map(float, p)) for p in dense], [tuple(map(int, t)) for t in plan.triangles])
    points = support.positions(mesh)
    nearest = [tree.find_nearest(tuple(map(float, p))) for p in points]
    distance = max(found[3] for found in nearest)
    diagonal = support.bbox_diagonal(points)
    check(distance < 1e-4 * diagonal, f"every point on the limit surface: within {distance / diagonal:.1e} of the "
                                      "diagonal of a level-6 limit mesh")
    normals = addon.blender.shading.read_corner_normals(mesh).reshape(-1, 3, 3)
    loops = support.read_array(mesh.loops, "vertex_index", dtype=np.int32).reshape(-1, 3)
    # On a crease each side's normal is its face's: measure each corner against the surface normal nearest to its
    # triangle's middle, which lies on the corner's side.
    middles = points[loops].mean(axis=1)
    side = np.array([tree.find_nearest(tuple(map(float, p)))[1] for p in middles])
    angle = np.degrees(np.arccos(np.clip(np.einsum("tkc,tc->tk", normals, side), -1.0, 1.0)))
    check(np.percentile(angle, 99) < 5.0,
          f"the normals are the surface's (99% within {np.percentile(angle, 99):.2f} degrees of the nearest face "
          "of the dense mesh on the same side)")
    # The creases part the normals, and nothing else does: a vertex has corners with different normals exactly where
    # it lies on the cube's edges (the limit of the creased sides, straight).
    spread = np.zeros(len(points))
    corner_normals = normals.reshape(-1, 3)
    for axis in range(3):
        low = np.full(len(points), np.inf)
        high = np.full(len(points), -np.inf)
        np.minimum.at(low, loops.ravel(), corner_normals[:, axis])
        np.maximum.at(high, loops.ravel(), corner_normals[:, axis])
        spread = np.maximum(spread, high - low)
    on_edges = (np.abs(np.abs(points) - 1.0) < 1e-5).sum(axis=1) >= 2  # object space: the cube's own
    check(np.array_equal(spread > 0.1, on_edges) and on_edges.any(),
          f"the normals part along the creases and nowhere else ({np.count_nonzero(on_edges)} vertices on them)")
    far = len(mesh.polygons)
    top_camera(3.0)
    bpy.context.view_layer.update()
    near = len(shown(obj).polygons)
    check(near > 2 * far, f"the scene camera moved twice as near (background mode: the viewport's view): finer, "
                          f"{near} triangles (was {far})")
    support.remove(obj)


def render_and_viewport_rates():
    """A render cuts at the Render dicing rate (what Apply gives), and the viewport gets its own back afterwards."""
    pixels_per_unit = top_camera(2.0)
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    obj = support.object_from_bmesh("Rendered", support.grid(cuts=2, size=2.0))
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=8.0, render_dicing_rate=2.0)
    viewport = len(shown(obj).polygons)
    seen = []

    def during_render(scene, *_):
        helper = stack.helper_of(obj, stack.entry(obj), create=False)
        seen.append(len(helper.data.polygons))

    bpy.app.handlers.render_post.append(during_render)
    try:
        bpy.ops.render.render()
    finally:
        bpy.app.handlers.render_post.remove(during_render)
    after = len(shown(obj).polygons)
    twin = support.copy_object(obj, "Rendered applied")
    twin.modifiers.clear()
    twin.loop_subdivision.use_adaptive = True
    twin.loop_subdivision.render_dicing_rate = 2.0
    support.apply_loop(twin)
    check(seen and seen[0] == len(twin.data.polygons) and seen[0] > viewport,
          f"the render cut at 2 px: {seen[0] if seen else None} triangles as Apply's {len(twin.data.polygons)} "
          f"(viewport {viewport}; {pixels_per_unit:.1f} px a unit at depth 1)")
    check(after == viewport, f"the viewport has its 8 px cut back after the render ({after})")
    support.remove(twin)
    support.remove(obj)


def no_camera():
    """No scene camera: the entry passes its input through and says why, and Apply refuses with the same words."""
    scene = bpy.context.scene
    camera = scene.camera
    scene.camera = None
    obj = support.object_from_bmesh("NoCamera", support.octahedron())
    bpy.ops.object.loop_subdivision_add(use_adaptive=True)
    cache = addon.live.engine.cache_of(obj)
    check(len(shown(obj).polygons) == 8 and cache is not None and "camera" in cache.error,
          f"the entry shows its input and says why: {cache.error if cache else None!r}")
    try:
        support.apply_loop(obj)
        refusal = ""
    except RuntimeError as error:  # an operator's error report, in background mode
        refusal = str(error)
    check("Adaptive Subdivision needs a scene camera" in refusal and len(obj.data.polygons) == 8,
          f"Apply refuses and says why ({refusal!r}); the mesh is unchanged")
    scene.camera = camera
    support.remove(obj)


# A second Blender adds an adaptive entry to the cage of the file it opens and prints how many triangles it shows, what
# its memory grew by (the peak of its resident memory, reset before, over what it held), and what the memory check
# counted: the add-on for Blender's side of the result, the core for its own (Tessellation.estimated_bytes).
PEAK_SCRIPT = """
import sys, bpy
sys.path.insert(0, {parent!r})
import {package} as addon
addon.register()
blender_side = []
estimate = addon.model.memory.estimate_output_bytes
def recorded(counts, core_bytes, **options):
    blender_side.append(estimate(counts, core_bytes, **options) - core_bytes)
    return blender_side[-1] + core_bytes
addon.model.memory.estimate_output_bytes = recorded

def status(field):
    with open("/proc/self/status") as file:
        return next(int(line.split()[1]) << 10 for line in file if line.startswith(field + ":"))

obj = bpy.data.objects["Cage"]
bpy.context.view_layer.objects.active = obj
obj.select_set(True)
bpy.context.view_layer.update()
held = status("VmRSS")
with open("/proc/self/clear_refs", "w") as file:
    file.write("5")  # resets the peak (VmHWM) to what is held now
bpy.ops.object.loop_subdivision_add(use_adaptive=True, {arguments})
triangles = len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)
obj.location.x += 0.0  # an edit that changes no rate: written in place
bpy.context.view_layer.update()
core = addon.live.engine.cache_of(obj).output.tessellation.estimated_bytes
print("PEAK", triangles, status("VmHWM") - held, blender_side[-1], core, flush=True)
"""


def book(pages):
    """Pages triangles on one edge (the spine from (0, 0, 0) to (0, 0, 1)), nothing else: fins, cards and foliage
    planes glued along an edge. Its spine is non-manifold, which the core once refined with every page around each
    corner: 100 pages at rate 3 took 17 GB."""
    angles = np.linspace(0.0, 2.0 * np.pi, pages, endpoint=False)
    vertices = [(0.0, 0.0, 0.0), (0.0, 0.0, 1.0)] + [(np.cos(a), np.sin(a), 0.5) for a in angles]
    mesh = bpy.data.meshes.new("Cage")
    mesh.from_pydata(vertices, [], [(0, 1, 2 + page) for page in range(pages)])
    obj = bpy.data.objects.new("Cage", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def memory_estimate():
    """Adding an entry with Adaptive Subdivision (its update, then an edit) grows Blender's memory by no more than the
    memory check counted (the add-on Blender's side, the core its own, each refusing past what is left): on Suzanne,
    whose irregular triangles the core refines through plans, and on an icosphere, all patches; over a million
    triangles each. A count below the growth would let Blender be killed for lack of memory. And on a book of 100
    triangles on one edge at rate 3 (Max Segments), in a few hundred MB at most."""
    cases = (("Suzanne", "dicing_rate=3.0", 1_000_000), ("Icosphere", "dicing_rate=3.0", 1_000_000),
             ("Book", "dicing_rate=0.5, max_rate=3, rules='OPENSUBDIV'", 100 * 9))
    for name, arguments, least in cases:
        support.clear_scene()
        top_camera(4.0, lens=50.0, resolution=1920, percentage=100)
        if name == "Suzanne":
            bpy.ops.mesh.primitive_monkey_add()
        elif name == "Icosphere":
            bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=5)
        else:
            support.select_only(book(100))
        obj = bpy.context.object
        obj.name = "Cage"
        support.shade_smooth(obj)
        with tempfile.TemporaryDirectory() as folder:
            blend = os.path.join(folder, "cage.blend")
            bpy.ops.wm.save_as_mainfile(filepath=blend, copy=True)
            script = PEAK_SCRIPT.format(parent=os.path.dirname(os.path.dirname(addon.__file__)),
                                        package=addon.__name__, arguments=arguments)
            code, output = support.run_blender(blend, script)
        line = next((text.split() for text in output.splitlines() if text.startswith("PEAK ")), None)
        if not check(code == 0 and line is not None, f"{name}: the second Blender measured its update (exit {code})"):
            print(output[-3000:])
            continue
        triangles, grown, blender_side, core = (int(word) for word in line[1:])
        counted = blender_side + core
        check(triangles >= least and counted >= grown,
              f"{name}, {triangles} triangles: Blender's memory grew by {grown / 2**20:.0f} MB; counted "
              f"{counted / 2**20:.0f} MB ({counted / grown:.2f}x): Blender's side {blender_side / 2**20:.0f}, the "
              f"core's {core / 2**20:.0f}")
        if name == "Book":
            check(grown <= 300 * 2**20 and counted <= 300 * 2**20,
                  f"the book takes a few hundred MB at most: {grown / 2**20:.0f} MB grown, "
                  f"{counted / 2**20:.0f} MB counted")


def core_refusal():
    """Where Blender's side of the result fits what is free but the core's own count (its plans for Suzanne's irregular
    triangles) does not fit what is left, the entry shows its input and says what the whole needs; with the memory
    free unknown, the same entry is made."""
    support.clear_scene()
    top_camera(4.0, lens=50.0, resolution=1920, percentage=100)
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.object
    memory = addon.model.memory
    estimate, available_bytes = memory.estimate_output_bytes, memory.available_bytes
    blender_side = []

    def recorded(counts, core_bytes, **options):
        blender_side.append(estimate(counts, core_bytes, **options) - core_bytes)
        return blender_side[-1] + core_bytes

    memory.estimate_output_bytes = recorded
    memory.available_bytes = lambda root="/": None
    try:
        bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=8.0)
        made = len(shown(obj).polygons)
        core = addon.live.engine.cache_of(obj).output.tessellation.estimated_bytes
        core_at_a_patch = memory.TESSELLATION_BYTES_PER_TRIANGLE * made * (1 + len(obj.data.uv_layers))
        bpy.ops.object.loop_subdivision_remove()
        # Free memory that leaves, after the reserve and Blender's side, room for the core at a patch's bytes a
        # triangle but not for its count.
        room = blender_side[-1] + (core_at_a_patch + core) // 2
        free = room
        while free - memory.reserve_bytes(free) < room:
            free += 1 << 20
        memory.available_bytes = lambda root="/": free
        bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=8.0)
        error = addon.live.engine.cache_of(obj).error
        need = memory.describe(blender_side[-1] + core, free, "")  # " needs about ...; ... are free, less ..."
        cage = len(obj.data.polygons)
        check(made > 100 * cage and core > core_at_a_patch and len(shown(obj).polygons) == cage
              and error.startswith("Adaptive Subdivision at 8 px (") and error.endswith(need),
              f"the core's count ({core / 2**20:.0f} MB, {core / made:.0f} bytes a triangle) past what is left: "
              f"the input shown, and {error!r}")
    finally:
        memory.estimate_output_bytes, memory.available_bytes = estimate, available_bytes
    support.remove(obj)


support.clear_scene()
defaults()
rates_from_the_camera()
edits_keep_the_cut()
camera_moves_cut_anew()
uvs_follow_uv_smooth()
limit_surface_without_cracks()
render_and_viewport_rates()
no_camera()
core_refusal()
memory_estimate()
check.finish()
