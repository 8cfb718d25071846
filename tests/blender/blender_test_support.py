"""Shared helpers of the Blender background tests (not a test itself: ctest runs only test_*.py).

Each test script imports this file from its own folder, registers the add-on from --addon-dir, builds meshes, runs
Blender's own Subdivision Surface modifier for reference, and ends with check.finish(), which prints a summary and
raises AssertionError on any failure so that `--python-exit-code 1` fails the run.
"""
import argparse
import contextlib
import importlib
import io
import os
import subprocess
import sys
import tempfile
import textwrap
import time
import traceback
import types

import bpy
import bmesh
import numpy as np

_started = time.time()


def load_addon(register=True):
    """Imports the add-on package from --addon-dir (its folder name is the package name) and registers it. Other
    arguments after "--" are the caller's (the benchmarks take some)."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-dir", required=True)
    args, _ = parser.parse_known_args(argv)
    addon_dir = os.path.abspath(args.addon_dir)
    sys.path.insert(0, os.path.dirname(addon_dir))
    package = importlib.import_module(os.path.basename(addon_dir))
    if register:
        package.register()
    return package


def blender_access(addon):
    """The add-on's Blender access (addon/blender/: mesh arrays, creases, shading, the stack and its node group) as one
    namespace, for the tests that read and write meshes the way the add-on does."""
    modules = (addon.blender.mesh_arrays, addon.blender.creases, addon.blender.shading, addon.blender.node_group,
               addon.blender.stack)
    return types.SimpleNamespace(**{name: getattr(module, name) for module in modules for name in dir(module)
                                    if not name.startswith("_")})


class Check:
    """Collects results so that one run reports every failure, then fails once at the end."""

    def __init__(self, name):
        self.name = name
        self.passed = 0
        self.failures = []

    def __call__(self, condition, what):
        if condition:
            self.passed += 1
            print(f"  ok    {what}")
        else:
            self.failures.append(what)
            print(f"  FAIL  {what}")
        return condition

    def finish(self):
        elapsed = time.time() - _started
        print(f"\n{self.name}: {self.passed} passed, {len(self.failures)} failed ({elapsed:.1f} s)")
        for what in self.failures:
            print(f"  failed: {what}")
        assert not self.failures, f"{self.name}: {len(self.failures)} checks failed"


def clear_scene():
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)


def object_from_bmesh(name, bm, triangulate=True):
    """A mesh object in the scene, made active and the only one selected. Triangulated here (not by the add-on)
    when Blender's own modifier must see the very same triangles."""
    if triangulate:
        bmesh.ops.triangulate(bm, faces=bm.faces[:])
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    select_only(obj)
    return obj


def shade_smooth(obj):
    """Shades every face of obj smooth (as Shade Smooth does) and returns obj: a cage whose limit normals are to show
    (the children of flat faces stay flat, as in Subdivision Surface)."""
    obj.data.polygons.foreach_set("use_smooth", np.ones(len(obj.data.polygons), dtype=bool))
    obj.data.update()
    return obj


def remove(obj):
    """Removes an object and its mesh when nothing else uses it."""
    mesh = obj.data
    bpy.data.objects.remove(obj)
    if mesh.users == 0:
        bpy.data.meshes.remove(mesh)


def select_only(*objects):
    bpy.context.view_layer.update()  # objects removed since the last update linger as None otherwise
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    for obj in objects:
        obj.select_set(True)
    bpy.context.view_layer.objects.active = objects[0]


def cube(name, subdivisions=0):
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=2.0)
    if subdivisions:
        bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=subdivisions, use_grid_fill=True)
    return bm


def icosphere(subdivisions=2):
    bm = bmesh.new()
    bmesh.ops.create_icosphere(bm, subdivisions=subdivisions, radius=1.0)
    return bm


def uv_sphere(segments=8, rings=6):
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=1.0)
    return bm


def octahedron():
    bm = bmesh.new()
    verts = [bm.verts.new(p) for p in ((1, 0, 0), (0, 1, 0), (-1, 0, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1))]
    for i in range(4):
        a, b = verts[i], verts[(i + 1) % 4]
        bm.faces.new((a, b, verts[4]))
        bm.faces.new((b, a, verts[5]))
    return bm


def creased_cube(compat, weight=1.0):
    """A cube cut 2x2 per side (triangulated) with its 12 sides creased: 24 crease edges in curves from corner to
    corner. Returns the object and the crease edges' indices."""
    obj = object_from_bmesh("CreasedCube", cube("CreasedCube", subdivisions=1))
    p = positions(obj.data)
    e = edges(obj.data)
    on_side = (np.abs(np.abs(p) - 1.0) < 1e-6).sum(axis=1) >= 2
    axis_aligned = (np.abs(p[e[:, 0]] - p[e[:, 1]]) > 1e-6).sum(axis=1) == 1  # not the triangulation's diagonals
    sides = np.flatnonzero(on_side[e[:, 0]] & on_side[e[:, 1]] & axis_aligned)
    assert len(sides) == 24
    set_edge_creases(obj.data, sides, weight, compat)
    return obj, sides


def grid(cuts=3, size=2.0):
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=cuts, y_segments=cuts, size=size / 2)
    return bm


def read_array(collection, name, width=1, dtype=np.float32):
    """A property of every element of a Blender collection, through foreach_get: (N,) or (N, width)."""
    values = np.empty(len(collection) * width, dtype=dtype)
    collection.foreach_get(name, values)
    return values if width == 1 else values.reshape(-1, width)


def positions(mesh):
    return read_array(mesh.vertices, "co", 3)


def edges(mesh):
    return read_array(mesh.edges, "vertices", 2, np.int32)


def edge_face_counts(mesh):
    return np.bincount(read_array(mesh.loops, "edge_index", dtype=np.int32), minlength=len(mesh.edges))


def set_edge_creases(mesh, edge_indices, weight, compat):
    weights = compat.read_edge_creases(mesh)
    weights[np.asarray(edge_indices, dtype=np.int64)] = weight
    compat.write_edge_creases(mesh, weights)


def blender_subdivision(obj, levels, boundary_smooth='ALL', use_limit_surface=False, uv_smooth='NONE'):
    """Blender's own Subdivision Surface (Catmull-Clark through OpenSubdiv) of obj, as a mesh copy (the caller removes
    it). The modifier is removed again, so obj is left as it was.

    With the limit surface, at Quality 10 (its most): Blender evaluates the limit on patches isolated to that level
    around irregular vertices, and lower qualities leave an error there (measured at the one-face corners of a
    triangulated grid, Boundary Smooth All: 6.5e-4 of the diagonal at Quality 3, 1.0e-5 at 6, 1e-7 at 10)."""
    modifier = obj.modifiers.new("Reference", 'SUBSURF')
    modifier.levels = levels
    modifier.use_limit_surface = use_limit_surface
    modifier.use_creases = True
    modifier.boundary_smooth = boundary_smooth
    modifier.uv_smooth = uv_smooth
    if use_limit_surface:
        modifier.quality = 10
    depsgraph = bpy.context.evaluated_depsgraph_get()
    result = bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph))
    obj.modifiers.remove(modifier)
    return result


def copy_object(obj, name):
    duplicate = obj.copy()
    duplicate.data = obj.data.copy()
    duplicate.name = name
    bpy.context.scene.collection.objects.link(duplicate)
    return duplicate


def bbox_diagonal(points):
    return float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))


def nearest_distances(points, cloud):
    """For each point, the distance to the nearest point of cloud and its index (brute force in blocks)."""
    points = np.asarray(points, dtype=np.float64)
    cloud = np.asarray(cloud, dtype=np.float64)
    distances = np.empty(len(points))
    indices = np.empty(len(points), dtype=np.int64)
    block = max(1, 4_000_000 // max(len(cloud), 1))
    for start in range(0, len(points), block):
        d = np.linalg.norm(points[start:start + block, None, :] - cloud[None, :, :], axis=2)
        indices[start:start + block] = d.argmin(axis=1)
        distances[start:start + block] = d.min(axis=1)
    return distances, indices


def apply_loop(obj, **arguments):
    select_only(obj)
    return bpy.ops.object.loop_subdivision_apply(**arguments)


def capture_output(function, stream=sys.stdout):
    """Runs function and returns (its result, what was printed to stream at the C level: on stdout operator
    reports, on sys.stderr Blender's own error lines)."""
    stream.flush()
    descriptor = stream.fileno()
    saved = os.dup(descriptor)
    with tempfile.TemporaryFile(mode="w+b") as capture:
        os.dup2(capture.fileno(), descriptor)
        try:
            result = function()
        finally:
            stream.flush()
            os.dup2(saved, descriptor)
            os.close(saved)
        capture.seek(0)
        text = capture.read().decode("utf-8", "replace")
    stream.write(text)
    return result, text


def raised_in_handlers(function):
    """Runs function; returns what Blender printed meanwhile of exceptions raised in handlers (the add-on's updates
    run in depsgraph_update_post; Blender prints their exceptions to sys.stderr and carries on)."""
    saved, sys.stderr = sys.stderr, io.StringIO()
    try:
        function()
        return sys.stderr.getvalue()
    finally:
        printed, sys.stderr = sys.stderr.getvalue(), saved
        sys.stderr.write(printed)


def tiny_render_camera(distance):
    """A camera looking down +y at the origin from distance, and the scene set to render 16 x 16 pixels with Cycles
    at one sample: renders that exercise the add-on, not the renderer. Returns the camera."""
    camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    bpy.context.scene.collection.objects.link(camera)
    camera.location = (0.0, -distance, 0.0)
    camera.rotation_euler = (np.pi / 2, 0.0, 0.0)
    scene = bpy.context.scene
    scene.camera = camera
    scene.render.engine = 'CYCLES'
    scene.cycles.samples = 1
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 16
    return camera


def exiting_script(body):
    """Python for a second Blender: body, then the process ends through os._exit, 1 (with the traceback printed) if
    body raised. Blender as a Python module can hang in its exit handlers (run_in_bpy.py)."""
    return ("import os, sys, traceback\ncode = 0\ntry:\n" + textwrap.indent(textwrap.dedent(body).strip(), "    ")
            + "\nexcept BaseException:\n    traceback.print_exc()\n    code = 1\n"
            "sys.stdout.flush()\nsys.stderr.flush()\nos._exit(code)\n")


# What the second Blender of run_blender runs where this one is Blender as a Python module: the steps of the program's
# command line, in a Python that imports bpy.
_BPY_PROLOGUE = "import bpy\n" + exiting_script("""
    blend, script, render = sys.argv[1], sys.argv[2], sys.argv[3:]
    bpy.ops.wm.open_mainfile(filepath=blend)
    exec(compile(script, "<python-expr>", "exec"), {"__name__": "__main__"})
    if render:
        output, first, last = render
        scene = bpy.context.scene
        scene.render.filepath, scene.frame_start, scene.frame_end = output, int(first), int(last)
        bpy.ops.render.render(animation=True)
""")


class Recorder:
    """A layout that records the labels drawn into it (and their icons); every other call is accepted."""

    def __init__(self, labels):
        self.__dict__["labels"] = labels

    def label(self, text="", icon='NONE', **_):
        self.labels.append((text, icon))

    def __getattr__(self, name):
        return lambda *args, **kwargs: Recorder(self.labels)

    def __setattr__(self, name, value):
        pass


class PanelStandIn:
    """What Blender hands the draw of the part of a modifier's panel: the modifier, and a layout (a Recorder)."""

    def __init__(self, modifier, labels):
        self.custom_data = modifier
        self.layout = Recorder(labels)


def drawn_labels(panel_class, modifier, context=None):
    """The texts of the labels panel_class's draw (as registered now) draws for a modifier."""
    labels = []
    panel_class.draw(PanelStandIn(modifier, labels), context or bpy.context)
    return [text for text, _ in labels]


def run_in_interface(steps, check):
    """Runs the generator steps in Blender's interface from a timer, as an artist's actions arrive between redraws
    (each step yields the seconds to wait before the next), then ends Blender with the checks' exit code: 1 on a
    failed check or an exception."""
    def run():
        try:
            return next(steps)
        except StopIteration:
            code = 0
        except BaseException:  # noqa: B036  (any failure fails the test)
            traceback.print_exc()
            code = 1
        try:
            check.finish()
        except AssertionError:
            code = 1
        sys.stdout.flush()
        os._exit(code)

    bpy.app.timers.register(run, first_interval=1.0, persistent=True)


def panel_labels(ui, obj, modifier):
    """The texts of the labels the add-on's panel (the add-on's ui module) draws for obj's entry modifier, notes on
    one line each."""
    labels = []
    ui._draw_settings(Recorder(labels), obj, modifier)
    return [text for text, _ in labels]


@contextlib.contextmanager
def memory_cgroup(limit):
    """A new memory cgroup (v2, or v1's memory controller) under this process's own, holding at most limit bytes; its
    directory, or None where this machine lets no cgroup be made (not root, no writable hierarchy). Processes that
    join it (run_blender's cgroup) are ended by the kernel's OOM killer past the limit, as Blender is on a desktop
    out of memory or in a render farm's slot."""
    made = None
    for line in open("/proc/self/cgroup").read().splitlines():
        hierarchy, controllers, path = line.split(":", 2)
        if hierarchy == "0" and not controllers:
            mount, limit_file = "/sys/fs/cgroup", "memory.max"
        elif "memory" in controllers.split(","):
            mount, limit_file = "/sys/fs/cgroup/memory", "memory.limit_in_bytes"
        else:
            continue
        directory = os.path.join(mount + path, f"loopsub-test-{os.getpid()}")
        try:
            os.mkdir(directory)
        except OSError:
            continue
        try:
            with open(os.path.join(directory, limit_file), "w") as file:
                file.write(str(limit))
            made = directory
            break
        except OSError:
            os.rmdir(directory)
    try:
        yield made
    finally:
        if made is not None:
            for _ in range(50):  # the kernel frees a cgroup a moment after its last process ends
                try:
                    os.rmdir(made)
                    break
                except OSError:
                    time.sleep(0.1)


def run_blender(blend, script, render=None, timeout=300, cgroup=None):
    """Runs script in a second Blender on the saved file blend, as `blender --background --factory-startup BLEND
    --python-exit-code 1 --python-expr SCRIPT` does; with render=(output, first, last) it then renders those frames
    as a render farm does, `-o OUTPUT -s FIRST -e LAST -a`. Where this Blender is a Python module (PyPI's bpy:
    bpy.app.binary_path is empty, there is no program), the second Blender is this interpreter importing bpy and
    taking the same steps: bpy.ops.wm.open_mainfile, the script, bpy.ops.render.render(animation=True) over the
    scene's frames set to first..last with its output path set to OUTPUT. cgroup: a directory from memory_cgroup that
    the second Blender runs in. Returns (exit code, stdout + stderr)."""
    if bpy.app.binary_path:
        command = [bpy.app.binary_path, "--background", "--factory-startup", blend, "--python-exit-code", "1",
                   "--python-expr", script]
        if render is not None:
            output, first, last = render
            command += ["-o", output, "-s", str(first), "-e", str(last), "-a"]
    else:
        command = [sys.executable, "-c", _BPY_PROLOGUE, blend, script]
        if render is not None:
            command += [str(value) for value in render]
    def join_cgroup():
        with open(os.path.join(cgroup, "cgroup.procs"), "w") as file:
            file.write(str(os.getpid()))

    process = subprocess.run(command, capture_output=True, text=True, timeout=timeout,
                             preexec_fn=join_cgroup if cgroup is not None else None)
    return process.returncode, process.stdout + process.stderr


def is_regular_crease(vert, creases):
    """RULES.md §1 for a bmesh vertex with two crease edges: interior, valence 6 with three faces on each side of the
    crease; boundary, valence 4 with the boundary edges as its creases."""
    if vert.is_boundary:
        return len(vert.link_edges) == 4 and all(edge.is_boundary for edge in creases)
    if len(vert.link_edges) != 6:
        return False
    edge, face, count = creases[0], creases[0].link_faces[0], 0
    while True:
        count += 1
        edge = next(e for e in face.edges if vert in e.verts and e != edge)
        if edge == creases[1]:
            return count == 3
        face = next(f for f in edge.link_faces if f != face)
