"""Blender side of scripts/demo.sh: subdivide a cage with the add-on and render it beside Blender's own subdivision.

Run inside Blender (scripts/demo.sh does it):
    blender --background --factory-startup --python-exit-code 1 --python scripts/demo_blender.py -- \
        [PATH.obj|PATH.blend] [--levels N] [--rules HOPPE94|OPENSUBDIV] [--out DIR]

Without a path the cage is built here: a tufted cushion with a creased seam, tagged corners and a UV map.
The add-on's Apply (limit surface, Keep Boundaries UVs, limit normals) and Blender's Subdivision Surface with the same
settings, both under a checker through the UV map.
Writes DIR/demo.blend (cage, Loop result, Subdivision Surface, camera and lights) and DIR/demo.png (Cycles, CPU).
Any failure raises, and --python-exit-code turns it into a non-zero exit status.
"""
import argparse
import math
import os
import sys
import time

import bpy
import bmesh
import numpy as np
from mathutils import Matrix, Vector

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if REPO not in sys.path:
    sys.path.insert(0, REPO)
from addon import native  # noqa: E402  (the working tree's built core module: its OBJ reader)
from addon.blender import creases  # noqa: E402  (the working tree's add-on: creases as each version keeps them)
from addon.model import geometry  # noqa: E402  (the crease mapping)

# Layout: every model is scaled so that its largest dimension is MODEL_SIZE, and the three stand SPACING apart on X.
MODEL_SIZE = 2.0
SPACING = 3.0
TURN = math.radians(-35)  # each model turns the same way, so the three read as one object seen three times
ELEVATION = math.radians(28)  # of the camera, looking along +Y
RESOLUTION = (960, 400)
SAMPLES = 24
UV_SMOOTH = 'PRESERVE_BOUNDARIES'  # Keep Boundaries: Subdivision Surface's default, and the add-on's
CHECKER_SCALE = 16.0  # squares per unit of UV: four across each face of the default cage's unwrap
BACKDROP = (0.80, 0.82, 0.85, 1.0)  # linear RGB behind the shadow-catching floor


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(
        prog="scripts/demo.sh",
        description="Loop-subdivide a cage with the add-on and render it beside Blender's Subdivision Surface.")
    parser.add_argument("path", nargs="?",
                        help=".obj or .blend file (default: a built-in tufted cushion; a model without a UV map is "
                             "unwrapped with Smart UV Project)")
    parser.add_argument("--levels", type=int, default=3, help="subdivision levels, 1-5 (default 3)")
    parser.add_argument("--rules", choices=("HOPPE94", "OPENSUBDIV"), default="HOPPE94",
                        help="the add-on's rule set (default HOPPE94, the add-on's own default)")
    parser.add_argument("--out", default=os.path.join(REPO, "out"), help="output directory (default out/)")
    args = parser.parse_args(argv)
    if not 1 <= args.levels <= 5:
        parser.error(f"--levels must be between 1 and 5, got {args.levels}")
    if args.path is not None:
        args.path = os.path.abspath(args.path)
        if not os.path.isfile(args.path):
            parser.error(f"no such file: {args.path}")
        if os.path.splitext(args.path)[1].lower() not in (".obj", ".blend"):
            parser.error(f"expected an .obj or .blend file, got {args.path}")
    args.out = os.path.abspath(args.out)
    return args


def register_addon():
    """The add-on is the package addon/ of this repository, registered directly rather than installed, so the demo
    always runs the working tree's code."""
    import addon
    addon.register()


# ---------------------------------------------------------------------------------------------------------------
# The cage


def default_cage():
    """A tufted cushion: a flattened box whose faces are split 2x2 and poked, so its triangles are symmetric. The seam
    around its middle, pushed out a little, is a closed crease (edge crease 1.0) whose four corners are tagged (vertex
    crease 1.0) so they stay pointed; the centre of the top is pulled in and tagged too, a tuft. The rest is smooth.
    Its UV map is the box's own unwrap (a cross of six squares, calc_uvs), split and poked with the faces: UV seams
    along the box's edges, where the checker must meet itself across the seam."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=1, use_grid_fill=True)
    bmesh.ops.poke(bm, faces=bm.faces[:])
    edge_crease, vertex_crease = creases.bmesh_crease_layers(bm)
    seam = {v for v in bm.verts if abs(v.co.z) < 1e-4}
    tuft = next(v for v in bm.verts if v.co.z > 0.999 and v.co.xy.length < 1e-4)
    for e in bm.edges:
        if seam.issuperset(e.verts):
            e[edge_crease] = 1.0
    for v in seam:
        v.co.xy *= 1.3
        if abs(v.co.x) > 1 and abs(v.co.y) > 1:
            v[vertex_crease] = 1.0
    tuft[vertex_crease] = 1.0
    tuft.co.z = 0.55
    for v in bm.verts:
        v.co.z *= 0.5
    mesh = bpy.data.meshes.new("Tufted cushion")
    bm.to_mesh(mesh)
    bm.free()
    return mesh, Matrix.Identity(4), {}


def crease_weight(sharpness):
    """Blender's crease weight for an OpenSubdiv sharpness, inverting Blender's own s = 10·c² as the add-on does."""
    return float(geometry.sharpness_to_crease(float(sharpness)))


def read_obj_tags(path):
    """OpenSubdiv's tags in the file (`t crease`, `t corner`, `t interpolateboundary`), which Blender's importer
    skips, as the project's own OBJ reader reads them (the core module's read_obj, the command line's reader): crease
    edges (a, b, Blender's crease weight), corner vertices (v, weight) and the boundary rule, or None."""
    obj = native.load().read_obj(path)
    edges = [(int(a), int(b), crease_weight(s)) for (a, b), s in zip(obj["crease_edges"], obj["crease_sharpness"])]
    corners = [(int(v), crease_weight(s)) for v, s in zip(obj["corner_vertices"], obj["corner_sharpness"])]
    boundary = {None: None, "edges-and-corners": 'KEEP_CORNERS'}.get(obj["boundary"], 'SMOOTH')
    return edges, corners, boundary


def obj_cage(path):
    bpy.ops.wm.obj_import(filepath=path)
    meshes = [o for o in bpy.context.selected_objects if o.type == 'MESH']
    if len(meshes) != 1:
        raise RuntimeError(f"{path}: expected one object, the file holds {len(meshes)}")
    obj = meshes[0]
    mesh, matrix = obj.data, obj.matrix_world.copy()
    bpy.data.objects.remove(obj)
    edges, corners, boundary = read_obj_tags(path)
    if edges or corners:
        # Blender's importer keeps the file's vertex order for a single object, so the tags' indices apply as is.
        bm = bmesh.new()
        bm.from_mesh(mesh)
        bm.verts.ensure_lookup_table()
        edge_crease, vertex_crease = creases.bmesh_crease_layers(bm)
        for a, b, w in edges:
            e = bm.edges.get((bm.verts[a], bm.verts[b])) if max(a, b) < len(bm.verts) and min(a, b) >= 0 else None
            if e is None:
                raise RuntimeError(f"{path}: crease tag names {a}-{b}, which is not an edge of the mesh")
            e[edge_crease] = w
        for v, w in corners:
            if not 0 <= v < len(bm.verts):
                raise RuntimeError(f"{path}: corner tag names vertex {v}, the mesh has {len(bm.verts)}")
            bm.verts[v][vertex_crease] = w
        bm.to_mesh(mesh)
        bm.free()
    return mesh, matrix, {"boundary": boundary} if boundary else {}


def blend_cage(path):
    """The active object of the file if it is a mesh, else its first mesh object by name. Only its mesh data and
    transform are taken: its modifiers, materials and the rest of the file stay out of the demo scene."""
    bpy.ops.wm.open_mainfile(filepath=path)
    active = bpy.context.view_layer.objects.active
    candidates = sorted((o for o in bpy.data.objects if o.type == 'MESH'), key=lambda o: o.name)
    if active is not None and active.type == 'MESH':
        candidates.insert(0, active)
    if not candidates:
        raise RuntimeError(f"{path}: no mesh object")
    name = candidates[0].name
    bpy.ops.wm.read_factory_settings(use_empty=True)
    with bpy.data.libraries.load(path) as (source, loaded):
        loaded.objects = [name]
    obj = loaded.objects[0]
    mesh, matrix = obj.data, obj.matrix_world.copy()
    bpy.data.objects.remove(obj)
    return mesh, matrix, {}


# ---------------------------------------------------------------------------------------------------------------
# The scene


def material(name, color, roughness):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    return mat


def checker_material(name, colors, roughness, uv_map):
    """A checker through the UV map (UV Map node into Checker Texture into the base colour): where UVs are smoothed,
    stretched or split, the squares show it."""
    mat = material(name, colors[0], roughness)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coordinates = nodes.new('ShaderNodeUVMap')
    coordinates.uv_map = uv_map
    checker = nodes.new('ShaderNodeTexChecker')
    checker.inputs["Scale"].default_value = CHECKER_SCALE
    checker.inputs["Color1"].default_value = (*colors[0], 1.0)
    checker.inputs["Color2"].default_value = (*colors[1], 1.0)
    links.new(coordinates.outputs["UV"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    return mat


def new_object(name, data, collection):
    obj = bpy.data.objects.new(name, data)
    collection.objects.link(obj)
    return obj


def set_materials(obj, *materials):
    obj.data.materials.clear()
    for mat in materials:
        obj.data.materials.append(mat)


def world_points(obj):
    """The evaluated object's vertices in world space, as an (N, 3) array."""
    evaluated = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = evaluated.to_mesh()
    local = np.empty(3 * len(mesh.vertices), dtype=np.float64)
    mesh.vertices.foreach_get("co", local)
    evaluated.to_mesh_clear()
    matrix = np.array(evaluated.matrix_world)
    return local.reshape(-1, 3) @ matrix[:3, :3].T + matrix[:3, 3]


def fit_matrix(mesh, matrix, x):
    """Object matrix that scales the cage to MODEL_SIZE, stands it on z = 0 at (x, 0) and turns it by TURN."""
    points = [matrix @ v.co for v in mesh.vertices]
    lo = Vector(min(p[i] for p in points) for i in range(3))
    hi = Vector(max(p[i] for p in points) for i in range(3))
    size = max(hi - lo)
    if size <= 0:
        raise RuntimeError("the cage has no extent")
    centre = Vector(((lo.x + hi.x) / 2, (lo.y + hi.y) / 2, lo.z))
    return (Matrix.Translation((x, 0, 0)) @ Matrix.Rotation(TURN, 4, 'Z') @ Matrix.Scale(MODEL_SIZE / size, 4)
            @ Matrix.Translation(-centre) @ matrix)


def stand_on_floor(obj):
    """Subdivision shrinks a smooth bottom off the floor: lower the evaluated object until it touches z = 0."""
    lowest = world_points(obj)[:, 2].min()
    obj.matrix_world = Matrix.Translation((0, 0, -lowest)) @ obj.matrix_world


def tag_markers(cage, collection, mat):
    """The cage's crease edges as tubes and its tagged corners as beads, in the cage's object space. Returns the
    caption that says what is shown."""
    mesh = cage.data
    radius = 0.018 * MODEL_SIZE / cage.matrix_world.to_scale().x
    edge_weights = creases.read_edge_creases(mesh)
    vertex_weights = creases.read_vertex_creases(mesh)
    markers = []
    creased = [e for e in mesh.edges if edge_weights[e.index] > 0]
    if creased:
        curve = bpy.data.curves.new("Crease edges", 'CURVE')
        curve.dimensions = '3D'
        curve.bevel_depth = radius
        curve.bevel_resolution = 2
        for e in creased:
            spline = curve.splines.new('POLY')
            spline.points.add(1)
            for point, vi in zip(spline.points, e.vertices):
                point.co = (*mesh.vertices[vi].co, 1.0)
        markers.append(new_object("Crease edges", curve, collection))
    corners = [v for v in mesh.vertices if vertex_weights[v.index] > 0]
    if corners:
        bm = bmesh.new()
        for v in corners:
            bmesh.ops.create_uvsphere(bm, u_segments=12, v_segments=8, radius=2.2 * radius,
                                      matrix=Matrix.Translation(v.co))
        beads = bpy.data.meshes.new("Corner tags")
        bm.to_mesh(beads)
        bm.free()
        for polygon in beads.polygons:
            polygon.use_smooth = True
        markers.append(new_object("Corner tags", beads, collection))
    for marker in markers:
        marker.data.materials.append(mat)
        marker.parent = cage
    shown = [what for what, present in (("creases", creased), ("corners", corners)) if present]
    return " and ".join(shown) + " in red" if shown else "no creases or corners tagged"


def label(text, size, location, camera, collection, mat):
    curve = bpy.data.curves.new(text, 'FONT')
    curve.body = text
    curve.size = size
    curve.align_x = 'CENTER'
    obj = new_object("Label: " + text, curve, collection)
    obj.data.materials.append(mat)
    obj.location = location
    obj.rotation_euler = camera.rotation_euler  # facing an orthographic camera: undistorted
    obj.visible_shadow = False
    return obj


def style_cage(cage, collection, uv_map):
    """Flat faces with the checker through its UV map, the edges drawn as thin dark bars (the Wireframe modifier keeps
    the faces and puts the bars in the second material slot), and the crease tags in red. Returns the caption for the
    tags."""
    cage.data.polygons.foreach_set("use_smooth", [False] * len(cage.data.polygons))
    set_materials(cage, checker_material("Cage", ((0.88, 0.88, 0.86), (0.45, 0.45, 0.44)), 0.6, uv_map),
                  material("Cage edges", (0.02, 0.02, 0.02), roughness=0.8))
    mesh = cage.data
    co = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", co)
    ends = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", ends)
    ends = ends.reshape(-1, 2)
    co = co.reshape(-1, 3)
    typical_edge = np.median(np.linalg.norm(co[ends[:, 0]] - co[ends[:, 1]], axis=1))
    wire = cage.modifiers.new("Edges", 'WIREFRAME')
    # Thin enough that a dense cage does not turn black; the scale is the cage's object scale (uniform, fit_matrix).
    wire.thickness = min(0.012 * MODEL_SIZE / cage.matrix_world.to_scale().x, 0.08 * typical_edge)
    wire.use_replace = False
    wire.use_even_offset = True
    wire.material_offset = 1
    return tag_markers(cage, collection, material("Crease tags", (0.85, 0.05, 0.03), roughness=0.3))


def ensure_uv_map(cage):
    """The name of the UV map the checker follows: the cage's active one, or, for a model without UVs (or whose UVs
    are all one point), one made with Smart UV Project (its islands' borders are the seams)."""
    mesh = cage.data
    uvs = np.empty(2 * len(mesh.loops), dtype=np.float32)
    if mesh.uv_layers:
        mesh.uv_layers.active.data.foreach_get("uv", uvs)
    if not mesh.uv_layers or np.ptp(uvs.reshape(-1, 2), axis=0).max() < 1e-6:
        bpy.ops.object.select_all(action='DESELECT')
        cage.select_set(True)
        bpy.context.view_layer.objects.active = cage
        if not mesh.uv_layers:
            mesh.uv_layers.new(name="UVMap")
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.select_all(action='SELECT')
        bpy.ops.uv.smart_project()
        bpy.ops.object.mode_set(mode='OBJECT')
        print("demo: the model has no UV map to show a checker with: unwrapped it with Smart UV Project")
    return mesh.uv_layers.active.name


def apply_loop(obj, levels, rules, boundary):
    """The add-on's Apply with Subdivision Surface's defaults for the limit surface and UVs, spelled out: the vertices
    on the limit surface, shaded with its normals (custom split normals, sharp across creases), UVs smoothed inside
    their islands and kept on their seams."""
    bpy.ops.object.select_all(action='DESELECT')
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    options = {"levels": levels, "rules": rules, "use_limit_surface": True, "uv_smooth": UV_SMOOTH}
    if boundary:
        options["boundary"] = boundary
    started = time.perf_counter()
    result = bpy.ops.object.loop_subdivision_apply(**options)
    if result != {'FINISHED'}:
        raise RuntimeError(f"loop_subdivision_apply({options}) returned {result}")
    print(f"demo: Loop subdivision to level {levels} ({rules}): {len(obj.data.polygons)} triangles "
          f"in {time.perf_counter() - started:.2f} s")


def add_subsurf(obj, levels, boundary):
    """Blender's Subdivision Surface with the settings the add-on was applied with: the same level, creases used
    (edge and vertex creases), the limit surface and Keep Boundaries UVs (both its defaults), the boundary mode."""
    subsurf = obj.modifiers.new("Subdivision", 'SUBSURF')
    subsurf.subdivision_type = 'CATMULL_CLARK'
    subsurf.levels = subsurf.render_levels = levels
    subsurf.use_creases = True
    subsurf.use_limit_surface = True
    subsurf.uv_smooth = UV_SMOOTH
    subsurf.boundary_smooth = 'PRESERVE_CORNERS' if boundary == 'KEEP_CORNERS' else 'ALL'


def shade_smooth(obj):
    """Shade Smooth, as an artist shades a model before subdividing it."""
    obj.data.polygons.foreach_set("use_smooth", [True] * len(obj.data.polygons))


def frame(scene, objects, captions):
    """An orthographic camera that frames the three models with their captions below them, whatever their shape."""
    collection = scene.collection
    camera_data = bpy.data.cameras.new("Camera")
    camera_data.type = 'ORTHO'
    camera = new_object("Camera", camera_data, collection)
    camera.rotation_euler = (math.pi / 2 - ELEVATION, 0, 0)
    scene.camera = camera
    right = np.array([1.0, 0.0, 0.0])
    up = np.array([0.0, math.sin(ELEVATION), math.cos(ELEVATION)])
    toward_camera = Vector((0.0, -math.cos(ELEVATION), math.sin(ELEVATION)))

    points = np.concatenate([world_points(obj) for obj in objects])
    u, v = points @ right, points @ up
    margin = 0.08 * MODEL_SIZE
    sizes = (0.13 * MODEL_SIZE, 0.085 * MODEL_SIZE, 0.085 * MODEL_SIZE)  # title, two lines of subtitle
    text_mat = material("Captions", (0.0, 0.0, 0.0), roughness=1.0)
    # Captions float between the camera and the scene, where nothing hides them; an orthographic camera draws them
    # the same size at any distance.
    texts = []
    for obj, lines in zip(objects, captions):
        baseline = v.min() - margin
        for text, size in zip(lines, sizes):
            baseline -= 1.25 * size
            location = Vector(obj.matrix_world.translation.x * right + baseline * up) + 10 * toward_camera
            texts.append(label(text, size, location, camera, collection, text_mat))
    bpy.context.view_layer.update()
    half_widths = [0.5 * t.dimensions.x for t in texts]
    u_lo = min(u.min(), *(t.location.x - w for t, w in zip(texts, half_widths))) - margin
    u_hi = max(u.max(), *(t.location.x + w for t, w in zip(texts, half_widths))) + margin
    v_lo, v_hi = baseline - 0.6 * sizes[-1], v.max() + margin
    aspect = RESOLUTION[0] / RESOLUTION[1]
    camera_data.ortho_scale = max(u_hi - u_lo, (v_hi - v_lo) * aspect)  # the width, as the picture is wide
    centre = 0.5 * (u_lo + u_hi) * right + 0.5 * (v_lo + v_hi) * up
    camera.location = Vector(centre) + 20 * MODEL_SIZE * toward_camera
    camera_data.clip_end = 40 * MODEL_SIZE


def light(scene):
    floor_mesh = bpy.data.meshes.new("Floor")
    floor_mesh.from_pydata([(-30, -30, 0), (30, -30, 0), (30, 30, 0), (-30, 30, 0)], [], [(0, 1, 2, 3)])
    floor = new_object("Floor", floor_mesh, scene.collection)
    # The floor only catches shadows, over a flat backdrop composited in: a lit floor and a visible sky would be
    # grainy at the few samples the demo can afford without a denoiser.
    floor.is_shadow_catcher = True

    sun_data = bpy.data.lights.new("Sun", 'SUN')
    sun_data.energy = 3.0
    sun_data.angle = math.radians(12)  # soft shadows
    sun = new_object("Sun", sun_data, scene.collection)
    sun.rotation_euler = (math.radians(52), 0, math.radians(-62))

    world = bpy.data.worlds.new("Sky")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.55, 0.62, 0.72, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.8
    scene.world = world


def build_scene(scene, mesh, matrix, levels, rules, boundary):
    cage = new_object("Cage", mesh, scene.collection)
    uv_map = ensure_uv_map(cage)  # before the copies, which take it with them
    objects = [cage] + [new_object(name, mesh.copy(), scene.collection)
                        for name in ("Loop subdivision", "Subdivision Surface")]
    for i, obj in enumerate(objects):
        obj.matrix_world = fit_matrix(mesh, matrix, (i - 1) * SPACING)
        obj.data.name = obj.name
    cage, loop, blender = objects

    tags_caption = style_cage(cage, scene.collection, uv_map)
    shade_smooth(loop)  # flat faces stay flat through both subdivisions, as in Blender's own
    apply_loop(loop, levels, rules, boundary)  # with the limit normals
    add_subsurf(blender, levels, boundary)
    shade_smooth(blender)
    # After apply, which rebuilds the mesh.
    set_materials(loop, checker_material("Loop result", ((0.88, 0.32, 0.05), (0.98, 0.70, 0.42)), 0.35, uv_map))
    set_materials(blender, checker_material("Subdivision Surface", ((0.12, 0.35, 0.75), (0.52, 0.70, 0.93)), 0.35,
                                            uv_map))
    stand_on_floor(loop)
    stand_on_floor(blender)

    rules_name = "Hoppe 94 rules" if rules == 'HOPPE94' else "OpenSubdiv rules"
    frame(scene, objects, (("Control cage", tags_caption, "UV checker, flat shaded"),
                           ("Loop subdivision", f"this add-on, level {levels}, {rules_name}",
                            "limit surface and limit normals"),
                           ("Subdivision Surface", f"Blender's modifier, level {levels}",
                            "limit surface, Shade Smooth")))
    light(scene)


def configure_render(scene, path):
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = SAMPLES
    # Debian's Blender is built without OpenImageDenoise: rendering fails with denoising on.
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 4  # matte models: more bounces cost time and change nothing visible
    scene.render.resolution_x, scene.render.resolution_y = RESOLUTION
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = 'PNG'
    scene.render.image_settings.color_mode = 'RGB'
    scene.render.filepath = path
    scene.render.film_transparent = True
    scene.use_nodes = True
    nodes, links = scene.node_tree.nodes, scene.node_tree.links
    backdrop = nodes.new('CompositorNodeAlphaOver')
    backdrop.inputs[1].default_value = BACKDROP
    links.new(nodes["Render Layers"].outputs["Image"], backdrop.inputs[2])
    links.new(backdrop.outputs["Image"], nodes["Composite"].inputs["Image"])


def strip_png_text(path):
    """Drops the PNG's text chunks, where Blender writes the .blend's path, the date and Cycles' render times: the
    picture is committed, and without them a rerun writes the very same file (Cycles' pixels are deterministic)."""
    with open(path, "rb") as f:
        data = f.read()
    kept, pos = [data[:8]], 8  # the signature, then chunks: length, type, data, CRC
    while pos < len(data):
        end = pos + 12 + int.from_bytes(data[pos:pos + 4], "big")
        if data[pos + 4:pos + 8] not in (b"tEXt", b"zTXt", b"iTXt"):
            kept.append(data[pos:end])
        pos = end
    with open(path, "wb") as f:
        f.write(b"".join(kept))


def main():
    args = parse_args()
    started = time.perf_counter()
    os.makedirs(args.out, exist_ok=True)
    blend_path = os.path.join(args.out, "demo.blend")
    png_path = os.path.join(args.out, "demo.png")

    if args.path is None:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        mesh, matrix, options = default_cage()
    elif args.path.lower().endswith(".obj"):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        mesh, matrix, options = obj_cage(args.path)
    else:
        mesh, matrix, options = blend_cage(args.path)
    if not len(mesh.polygons):
        raise RuntimeError(f"{args.path}: the mesh has no faces")
    register_addon()

    scene = bpy.context.scene
    build_scene(scene, mesh, matrix, args.levels, args.rules, options.get("boundary"))
    configure_render(scene, png_path)  # before saving, so that the .blend renders the same picture
    bpy.ops.wm.save_as_mainfile(filepath=blend_path, check_existing=False)

    if os.path.exists(png_path):
        os.remove(png_path)  # so that a render that writes nothing cannot pass for one that did
    print(f"demo: rendering {RESOLUTION[0]}x{RESOLUTION[1]} at {SAMPLES} samples with Cycles on the CPU "
          "(10 s on two idle cores, up to a minute on busy ones)", flush=True)
    render_started = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(png_path):
        raise RuntimeError(f"rendering wrote no picture at {png_path}")
    strip_png_text(png_path)
    print(f"demo: rendered in {time.perf_counter() - render_started:.1f} s; "
          f"total {time.perf_counter() - started:.1f} s")
    print(f"demo: scene   {blend_path}")
    print(f"demo: picture {png_path}")


main()
