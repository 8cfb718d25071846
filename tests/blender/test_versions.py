"""What differs between Blender versions in normals, seams and shading, checked as an artist meets it, in whichever
Blender runs this (3.4.1 and the bpy wheels 4.2, 4.5, 5.0, 5.2, 5.3 here):

- Custom normals (docs/addon.md, Normals): a cage that shades with custom normals of its own gives a result that
  shades with them, interpolated per face (as corner attributes are) and normalised, with Use Limit Surface on or off,
  through Apply and through the modifier. From 4.5 they are the corner attribute "custom_normal": tangent space
  (short2, what normals_split_custom_set writes) or "free" (a float vector on any domain, e.g. from a Set Mesh Normal
  node or written directly); no stray copy ("custom_normal.001") and no warning about it.
- UV seams: the child edges on a seam are seams, the others not, with one seam attribute (4.5 renamed ".uv_seam" to
  "uv_seam", which a generic copy of edge attributes duplicated as "uv_seam.001").
- A file saved by Blender 3.4 with Auto Smooth on, opened in 4.1+ (run there only; Debian's `blender` 3.4 makes the
  file at test time and must be on PATH): Blender appends an "Auto Smooth" Geometry Nodes modifier to the objects
  whose mesh had it (the owner, after the entry, and the entry's hidden helper). The entry still subdivides, the
  result shades as 3.4 showed it (limit normals; Auto Smooth where the result has Blender's own normals), and no
  modifier is left on a helper.
- 4.0 (not installed here): Mesh.corner_normals is empty there until calc_normals_split() ran;
  compat.read_corner_normals takes the old way on 4.0, which nothing here can run.
"""
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
compat = support.blender_access(addon)
check = support.Check("test_versions")
ADDON_DIR = os.path.dirname(addon.__file__)
VERSION = bpy.app.version

# Corner normals compared with those another Blender showed, or with Blender's own storage of the expected ones
# (custom normals in tangent space come back rounded: two 16-bit factors in the corner's normal space).
ANGLE_TOLERANCE = 0.1  # degrees
LENGTH_TOLERANCE = 1e-3


def angles(a, b):
    """Degrees between the rows of a and b."""
    a = np.asarray(a, np.float64)
    b = np.asarray(b, np.float64)
    cosines = (a * b).sum(axis=1) / (np.linalg.norm(a, axis=1) * np.linalg.norm(b, axis=1))
    return np.degrees(np.arccos(np.clip(cosines, -1.0, 1.0)))


def stray_copies(mesh, name):
    """Attributes that repeat name besides the one Blender keeps it in: "name.001" and the like (the dot that hides
    a built-in name from the interface, ".uv_seam" up to 4.4, counts as the same name)."""
    found = [a.name for a in mesh.attributes if a.name.lstrip(".").split(".")[0] == name]
    return sorted(found)[1:] if len(found) > 1 else []


def evaluated_mesh(obj):
    return obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data


def shown_normals(mesh):
    """The normal Blender shades each corner with, read from Blender (not through the add-on): Mesh.corner_normals
    from 4.1, calc_normals_split() and MeshLoop.normal before."""
    values = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    if VERSION >= (4, 1, 0):
        mesh.corner_normals.foreach_get("vector", values)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", values)
        mesh.free_normals_split()
    return values.reshape(-1, 3)


def add_entry(obj, **arguments):
    support.select_only(obj)
    assert bpy.ops.object.loop_subdivision_add(**arguments) == {'FINISHED'}


def smooth_cage(name):
    """A cube cut once per side, triangulated, every face smooth."""
    obj = support.object_from_bmesh(name, support.cube(name, subdivisions=1))
    obj.data.polygons.foreach_set("use_smooth", np.ones(len(obj.data.polygons), dtype=bool))
    obj.data.update()
    return obj


# --- custom normals -------------------------------------------------------------------------------------------------

EDITS = 12
# A corner attribute carrying the cage's corner normals, which the add-on interpolates per face as it does any.
EXPECTED = "expected_normal"


def radial(points):
    """Unit vectors away from the centre, bent a little so that they are no plane's normal."""
    vectors = np.asarray(points, np.float32) + np.float32([0.3, -0.2, 0.1])
    return vectors / np.linalg.norm(vectors, axis=1, keepdims=True)


def set_tangent_space_normals(mesh):
    """What every version has: normals_split_custom_set (stored in tangent space; Auto Smooth on up to 4.0)."""
    if hasattr(mesh, "use_auto_smooth"):
        mesh.use_auto_smooth = True
    corner_vertices = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
    mesh.normals_split_custom_set(radial(support.positions(mesh))[corner_vertices])


def free_normal_setter(domain):
    """4.5+: free normals, a float vector attribute "custom_normal" written directly on domain."""
    def set_free(mesh):
        if domain == 'POINT':
            values = radial(support.positions(mesh))
        else:  # one normal per corner, each face's own mix: corners of a vertex differ
            corner_vertices = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
            corner_faces = np.repeat(np.arange(len(mesh.polygons)),
                                     support.read_array(mesh.polygons, "loop_total", dtype=np.int32))
            face_normals = support.read_array(mesh.polygons, "normal", 3)
            values = radial(support.positions(mesh))[corner_vertices] + 0.5 * face_normals[corner_faces]
            values /= np.linalg.norm(values, axis=1, keepdims=True)
        attribute = mesh.attributes.new("custom_normal", 'FLOAT_VECTOR', domain)
        attribute.data.foreach_set("vector", np.ascontiguousarray(values, np.float32).ravel())
        mesh.update()
    return set_free


def custom_normal_kinds():
    kinds = {"tangent-space custom normals": set_tangent_space_normals}
    if VERSION >= (4, 5, 0):
        kinds["free custom normals per corner"] = free_normal_setter('CORNER')
        kinds["free custom normals per vertex"] = free_normal_setter('POINT')
    return kinds


def note_expected(mesh):
    """What the cage shades with, read back (tangent space stores them a little rounded, and turns them with the
    faces when vertices move), as a plain corner attribute."""
    normals = shown_normals(mesh)  # first: in 3.4 computing them moves the corner layers, and attributes with them
    expected = mesh.attributes.get(EXPECTED)
    if expected is None:
        expected = mesh.attributes.new(EXPECTED, 'FLOAT_VECTOR', 'CORNER')
    expected.data.foreach_set("vector", normals.ravel())
    mesh.update()


def custom_normal_cage(name, set_normals):
    obj = smooth_cage(name)
    obj.data.uv_layers.new(name="UVMap")  # each face its own square: the corners of a vertex have UVs of their own
    set_normals(obj.data)
    note_expected(obj.data)
    return obj


def storage_error(obj, expected):
    """Degrees that Blender's own storage of the normals expected (normals_split_custom_set, tangent space) loses on
    obj's evaluated mesh (the same lnor spaces as the result's)."""
    mesh = bpy.data.meshes.new_from_object(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()))
    if hasattr(mesh, "use_auto_smooth"):
        mesh.use_auto_smooth = True
    free = mesh.attributes.get("custom_normal")
    if free is not None and free.data_type == 'FLOAT_VECTOR':
        mesh.attributes.remove(free)  # normals_split_custom_set leaves a mesh with free normals as it is
    mesh.normals_split_custom_set(expected)
    error = float(angles(shown_normals(mesh), expected).max())
    bpy.data.meshes.remove(mesh)
    return error


def custom_normal_error(obj):
    """How far obj's evaluated mesh shades from the cage's custom normals interpolated per face and normalised:
    (worst angle in degrees, what Blender's own storage of those loses, worst departure from unit length)."""
    mesh = evaluated_mesh(obj)
    normals = shown_normals(mesh)
    expected = support.read_array(mesh.attributes[EXPECTED].data, "vector", 3)
    expected /= np.linalg.norm(expected, axis=1, keepdims=True)
    lengths = np.linalg.norm(normals, axis=1)
    with np.errstate(invalid='ignore'):
        worst = float(np.nan_to_num(angles(normals, expected), nan=180.0).max())
    return worst, storage_error(obj, expected), float(np.nan_to_num(np.abs(lengths - 1.0), nan=1.0).max())


def within(worst, storage, length_error):
    return worst <= max(ANGLE_TOLERANCE, storage + 0.01) and length_error <= LENGTH_TOLERANCE


def check_custom_normals(what, obj):
    worst, storage, length_error = custom_normal_error(obj)
    check(within(worst, storage, length_error),
          f"{what}: shades with the cage's custom normals, interpolated per face and normalised (within "
          f"{worst:.3f} degrees, Blender's storage of them {storage:.3f}; lengths within {length_error:.1e} of 1)")
    mesh = evaluated_mesh(obj)
    strays = stray_copies(mesh, "custom_normal")
    check(not strays, f"{what}: no stray copy of the custom normals ({strays or 'none'})")
    if VERSION >= (4, 5, 0):
        # Free normals are a copy; tangent space costs Blender's normal spaces on every update (1.5 s at 730,000
        # corners in 5.3), whichever way the cage keeps its own.
        stored = mesh.attributes.get("custom_normal")
        kind = None if stored is None else (stored.data_type, stored.domain)
        check(kind == ('FLOAT_VECTOR', 'CORNER'), f"{what}: the result's are free normals per corner ({kind})")


def custom_normals():
    for kind, set_normals in custom_normal_kinds().items():
        for limit in (True, False):
            label = f"{kind}, Use Limit Surface {'on' if limit else 'off'}"
            obj = custom_normal_cage("CustomApply", set_normals)
            result, output = support.capture_output(
                lambda: support.apply_loop(obj, levels=1, rules='OPENSUBDIV', use_limit_surface=limit))
            check(result == {'FINISHED'}, f"{label}: Apply runs")
            check_custom_normals(f"{label}, Apply", obj)
            check("custom_normal" not in output, f"{label}: Apply reports nothing about an attribute custom_normal")
            support.remove(obj)

            obj = custom_normal_cage("CustomModifier", set_normals)
            add_entry(obj, levels=1, rules='OPENSUBDIV', use_limit_surface=limit)
            mesh = evaluated_mesh(obj)
            cage_faces = len(obj.data.polygons)
            check(len(mesh.polygons) == 4 * cage_faces, f"{label}: the modifier subdivides")
            check_custom_normals(f"{label}, modifier", obj)
            check_edits(label, obj)
            support.remove(obj)


def edited_values(mesh, positions):
    """What check_edits changes: the positions, or the UV map."""
    return support.positions(mesh) if positions else support.read_array(mesh.uv_layers[0].data, "uv", 2)


def check_edits(label, obj):
    """Edits in a row, each written into the result in place: a vertex moved, then a UV moved alone (a corner whose
    UV no other corner of its vertex shares, so that the plan stays). After each, the result follows it, still
    shades with the cage's custom normals (in tangent space they turn with the faces), and the update raised
    nothing."""
    mesh = obj.data
    corner_vertices = support.read_array(mesh.loops, "vertex_index", dtype=np.int32)
    keys = [(vertex, *uv) for vertex, uv in zip(corner_vertices.tolist(), support.read_array(
        mesh.uv_layers[0].data, "uv", 2).tolist())]
    alone = [corner for corner, key in enumerate(keys) if keys.count(key) == 1]
    assert len(alone) >= EDITS // 2
    builds = addon.live.engine.cache_of(obj).plan_builds
    failures = []
    for edit in range(EDITS):
        moves_vertex = edit % 2 == 0
        what = "a vertex moved" if moves_vertex else "a UV moved"
        before = edited_values(evaluated_mesh(obj), moves_vertex)

        def change():
            if moves_vertex:
                obj.data.vertices[edit].co.z += 0.01
            else:
                obj.data.uv_layers[0].data[alone[edit // 2]].uv[0] += 0.001
            note_expected(obj.data)
            evaluated_mesh(obj)  # the update, in depsgraph_update_post
        raised = support.raised_in_handlers(change)
        raised = raised.strip().splitlines()[-1] if "Traceback" in raised else ""
        worst, storage, length_error = custom_normal_error(obj)
        followed = not np.array_equal(edited_values(evaluated_mesh(obj), moves_vertex), before)
        problem = (addon.live.engine.cache_of(obj).error or raised or ("" if followed else "the result did not follow")
                   or ("" if within(worst, storage, length_error)
                       else f"{worst:.3f} degrees, lengths within {length_error:.1e} of 1"))
        if problem:
            failures.append(f"edit {edit + 1} ({what}): {problem}")
    builds = addon.live.engine.cache_of(obj).plan_builds - builds
    check(not failures and builds == 0,
          f"{label}, modifier: {EDITS} edits in a row (a vertex, a UV), each followed in place ({builds} new plans), "
          f"still shaded with the cage's custom normals, nothing raised ({failures[:3] or 'none'})")


# --- UV seams -------------------------------------------------------------------------------------------------------

def expected_child_seams(cage_edges, cage_seams, cage_vertices, result_edges):
    """Level 1: the result keeps the cage's vertex indices, and each new vertex lies on one cage edge, whose two ends
    are its only neighbours among the cage's vertices. A child edge from a cage vertex to a new vertex lies on that
    cage edge; edges between new vertices lie inside a cage face."""
    seams = {tuple(sorted(edge)) for edge in cage_edges[cage_seams].tolist()}
    old_neighbours = {}
    for a, b in result_edges.tolist():
        if (a < cage_vertices) != (b < cage_vertices):
            old, new = (a, b) if a < cage_vertices else (b, a)
            old_neighbours.setdefault(new, set()).add(old)
    expected = np.zeros(len(result_edges), dtype=bool)
    for index, (a, b) in enumerate(result_edges.tolist()):
        if (a < cage_vertices) != (b < cage_vertices):
            new = b if a < cage_vertices else a
            expected[index] = tuple(sorted(old_neighbours[new])) in seams
    return expected


def seam_cage(name):
    """A smooth cube with seams around its middle (the cut's edges at z = 0) and down one side."""
    obj = smooth_cage(name)
    mesh = obj.data
    points = support.positions(mesh)
    edges = support.edges(mesh)
    middle = (np.abs(points[edges[:, 0], 2]) < 1e-6) & (np.abs(points[edges[:, 1], 2]) < 1e-6)
    side = ((np.abs(points[edges, 0] - 1) < 1e-6) & (np.abs(points[edges, 1]) < 1e-6)).all(axis=1)
    seams = middle | side
    mesh.edges.foreach_set("use_seam", seams)
    mesh.update()
    assert seams.sum() == 10
    return obj, edges, seams, len(mesh.vertices)


def check_seams(what, mesh, cage_edges, cage_seams, cage_vertices):
    result_edges = support.edges(mesh)
    seams = support.read_array(mesh.edges, "use_seam", dtype=bool)
    expected = expected_child_seams(cage_edges, cage_seams, cage_vertices, result_edges)
    check(np.array_equal(seams, expected),
          f"{what}: seams on exactly the {int(expected.sum())} child edges of the {int(cage_seams.sum())} seam edges "
          f"({int(seams.sum())} seams, {int((seams != expected).sum())} edges wrong)")
    strays = stray_copies(mesh, "uv_seam")
    check(not strays, f"{what}: one seam attribute, no stray copy ({strays or 'none'})")


def seams():
    for limit in (True, False):
        label = f"UV seams, Use Limit Surface {'on' if limit else 'off'}"
        obj, edges, marked, vertices = seam_cage("SeamApply")
        result, _ = support.capture_output(
            lambda: support.apply_loop(obj, levels=1, rules='OPENSUBDIV', use_limit_surface=limit))
        check(result == {'FINISHED'}, f"{label}: Apply runs")
        check_seams(f"{label}, Apply", obj.data, edges, marked, vertices)
        support.remove(obj)

        obj, edges, marked, vertices = seam_cage("SeamModifier")
        add_entry(obj, levels=1, rules='OPENSUBDIV', use_limit_surface=limit)
        check_seams(f"{label}, modifier", evaluated_mesh(obj), edges, marked, vertices)
        support.remove(obj)


# --- a file saved by 3.4 with Auto Smooth, opened in 4.1+ -----------------------------------------------------------

# Runs in Debian's Blender 3.4: two cages with Auto Smooth on at 20 degrees (a Loop subdivision of the cube shows
# edges sharper than that) and a Loop Subdivision entry each, saved; the corner normals 3.4 shows, to .npy files.
#   Limit:     Use Limit Surface on: its result holds the limit normals
#   Plain:     Use Limit Surface off: Blender's normals, split by Auto Smooth
MAKE_34_FILE = r"""
import importlib, math, os, sys
import bpy, bmesh
import numpy as np
addon_dir, folder = sys.argv[sys.argv.index("--") + 1:][:2]
sys.path.insert(0, os.path.dirname(addon_dir))
addon = importlib.import_module(os.path.basename(addon_dir))
addon.register()
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
bpy.context.view_layer.update()

def cage(name, limit):
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=2.0)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=1, use_grid_fill=True)
    bmesh.ops.triangulate(bm, faces=bm.faces[:])
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    mesh.use_auto_smooth = True
    mesh.auto_smooth_angle = math.radians(20)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    assert bpy.ops.object.loop_subdivision_add(levels=1, use_limit_surface=limit) == {'FINISHED'}
    return obj

def save_normals(obj):
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    mesh.calc_normals_split()
    normals = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    mesh.loops.foreach_get("normal", normals)
    np.save(os.path.join(folder, obj.name + ".npy"), normals.reshape(-1, 3))

shown = [cage("Limit", True), cage("Plain", False)]
addon.live.engine.refresh_all()
for obj in shown:
    save_normals(obj)
bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "auto_smooth_34.blend"))
print("MADE", bpy.app.version_string)
"""


def file_from_34():
    """From 4.1: a 3.4 file with Auto Smooth opens with Blender's Auto Smooth modifiers appended."""
    if VERSION < (4, 1, 0):
        print("  (Auto Smooth from a 3.4 file: only Blender 4.1+ converts it; nothing to check here)")
        return
    blender = shutil.which("blender")
    if not check(blender is not None, "Debian's Blender 3.4 ('blender' on PATH) is there to make the 3.4 file"):
        return
    folder = tempfile.mkdtemp(prefix="loop_versions_")
    # The environment as this process started, not as bpy left it: bpy 5.2 points OCIO at its own colour
    # configuration (set from C, so os.environ does not show it), which 3.4's OpenColorIO cannot read.
    environment = {key: value for key, value in os.environ.items() if key != "OCIO"}
    process = subprocess.run([blender, "--background", "--factory-startup", "--python-exit-code", "1",
                              "--python-expr", MAKE_34_FILE, "--", ADDON_DIR, folder],
                             capture_output=True, text=True, timeout=300, env=environment)
    made = process.returncode == 0 and "MADE 3.4" in process.stdout
    if not check(made, "Blender 3.4 made a file with two Auto Smooth cages and their entries"):
        print(process.stdout[-3000:], process.stderr[-3000:])
        return
    bpy.ops.wm.open_mainfile(filepath=os.path.join(folder, "auto_smooth_34.blend"))
    for name in ("Limit", "Plain"):
        obj = bpy.data.objects[name]
        cage_faces = len(obj.data.polygons)
        obj.loop_subdivision.levels = 2
        faces_2 = len(evaluated_mesh(obj).polygons)
        obj.loop_subdivision.levels = 1
        faces_1 = len(evaluated_mesh(obj).polygons)
        check(faces_2 == 16 * cage_faces and faces_1 == 4 * cage_faces,
              f"{name}: the entry still subdivides in {bpy.app.version_string} (Levels 2: {faces_2} faces, "
              f"1: {faces_1}; the cage has {cage_faces})")
    for name in ("Limit", "Plain"):
        obj = bpy.data.objects[name]
        normals = shown_normals(evaluated_mesh(obj))
        shown_34 = np.load(os.path.join(folder, name + ".npy"))
        worst = float(angles(normals, shown_34).max()) if normals.shape == shown_34.shape else float("inf")
        check(worst <= ANGLE_TOLERANCE,
              f"{name}: shades as Blender 3.4 showed it (corner normals within {worst:.3f} degrees); modifiers "
              f"{[modifier.name for modifier in obj.modifiers]}")
    helpers = [obj for obj in bpy.data.objects if obj.get(addon.blender.stack.OWNER_TAG) is not None]
    carrying = {obj.name: [modifier.name for modifier in obj.modifiers] for obj in helpers if len(obj.modifiers)}
    check(len(helpers) == 2 and not carrying, f"the entries' hidden helpers carry no modifier ({carrying or 'none'})")
    shutil.rmtree(folder, ignore_errors=True)


custom_normals()
seams()
file_from_34()  # last: it opens another file
check.finish()
