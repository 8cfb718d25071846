"""Use Limit Surface and UV Smooth in Blender: the settings under Blender's own names, the limit positions, the limit
normals written as custom split normals (split across creases, shared elsewhere), custom normals a mesh already had,
and a Beauty-triangulated Suzanne made as an artist makes it.

Blender stores a custom normal as two 16-bit factors in the corner's normal space, so normals read back from a mesh
are compared within 1e-3 (an angle of about 0.06 degrees), or, where that storage loses more (a custom normal far
from the face's own), within what Blender keeps of the same normals set directly on the same mesh.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402
import bmesh  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
compat = support.blender_access(addon)
check = support.Check("test_limit")
NORMAL_TOLERANCE = 1e-3


def core():
    from importlib import import_module
    return import_module(addon.__name__ + "._loopsub")


def run_apply(obj, **arguments):
    support.select_only(obj)
    return support.capture_output(lambda: bpy.ops.object.loop_subdivision_apply(**arguments))


def corner_normals(mesh):
    """(T, 3, 3): the normal Blender shades each corner of each triangle with."""
    return compat.read_corner_normals(mesh).reshape(-1, 3, 3)


def loop_vertices(mesh):
    return support.read_array(mesh.loops, "vertex_index", dtype=np.int32)


def vertex_spread(mesh):
    """Per vertex, the largest difference between the normals of its corners."""
    normals = compat.read_corner_normals(mesh)
    vertices = loop_vertices(mesh)
    low = np.full((len(mesh.vertices), 3), np.inf)
    high = np.full((len(mesh.vertices), 3), -np.inf)
    np.minimum.at(low, vertices, normals)
    np.maximum.at(high, vertices, normals)
    return (high - low).max(axis=1)


# --- the settings: Blender's names, defaults and words ---------------------------------------------------------------

def settings_as_blender():
    subsurf = bpy.types.SubsurfModifier.bl_rna.properties
    for ours, where in ((addon.ui.properties.LoopSubdivisionSettings.bl_rna.properties, "settings"),
                        (bpy.ops.object.loop_subdivision_apply.get_rna_type().properties, "Apply"),
                        (bpy.ops.object.loop_subdivision_add.get_rna_type().properties, "Add")):
        for name in ("use_limit_surface", "uv_smooth"):
            same = ours[name].name == subsurf[name].name and ours[name].description == subsurf[name].description
            if name == "uv_smooth":
                same &= ([(i.identifier, i.name, i.description) for i in ours[name].enum_items]
                         == [(i.identifier, i.name, i.description) for i in subsurf[name].enum_items])
            check(same, f"{where}: {name} has Subdivision Surface's label, description (and items)")
        check(ours["use_limit_surface"].default is True and ours["uv_smooth"].default == 'PRESERVE_BOUNDARIES',
              f"{where}: defaults as a new Subdivision Surface's: Use Limit Surface on, UV Smooth Keep Boundaries")


def script_call():
    """The call the issue names, from a script, on a UV-mapped cube."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    obj = support.shade_smooth(support.object_from_bmesh("ScriptCall", bm))  # flat faces stay flat: flat_faces
    cage = support.positions(obj.data)
    mesh = obj.data
    mesh.calc_loop_triangles()
    triangles = support.read_array(mesh.loop_triangles, "vertices", 3, np.int32)
    support.select_only(obj)
    result = bpy.ops.object.loop_subdivision_apply(levels=2, rules='OPENSUBDIV', use_limit_surface=True,
                                                   uv_smooth='PRESERVE_CORNERS')
    plan = core().Plan(triangles, len(cage), 2, rules="opensubdiv", limit_surface=True)
    limit, normals = plan.evaluate_with_normals(cage)
    got = support.positions(obj.data)
    check(result == {'FINISHED'} and np.array_equal(got, limit),
          "loop_subdivision_apply(levels=2, rules='OPENSUBDIV', use_limit_surface=True, "
          "uv_smooth='PRESERVE_CORNERS') puts the vertices on the core's limit surface")
    written = corner_normals(obj.data)
    difference = np.abs(written - normals).max()
    check(obj.data.has_custom_normals and difference < NORMAL_TOLERANCE,
          f"the result shades with the core's limit normals as custom split normals (within {difference:.1e})")
    if compat.HAS_FREE_NORMALS:
        # A smooth closed cage: one normal per vertex, which 4.5+ keeps as free normals exactly as the core gives them
        # (the core writes them into the new mesh's attribute itself).
        _, vertex_normals = plan.evaluate_with_limit_normals(cage)
        stored = obj.data.attributes.get("custom_normal")
        kept = (stored is not None and (stored.domain, stored.data_type) == ('POINT', 'FLOAT_VECTOR')
                and np.array_equal(support.read_array(stored.data, "vector", 3), vertex_normals))
        check(kept, "4.5+: the limit normals are the free normals of the result's vertices, bit for bit the core's")
    check(bool(support.read_array(obj.data.polygons, "use_smooth", dtype=bool).all()),
          "every face of the result is shaded smooth, as the cage's")
    if hasattr(obj.data, "use_auto_smooth"):
        check(obj.data.use_auto_smooth, "Blender 3.x: Auto Smooth is on, so the custom normals shade")
    support.remove(obj)

    obj = support.object_from_bmesh("LimitOff", support.cube("LimitOff"))
    cage = support.positions(obj.data)
    run_apply(obj, levels=2, rules='OPENSUBDIV', use_limit_surface=False)
    refined = core().Plan(triangles, len(cage), 2, rules="opensubdiv").evaluate(cage)
    check(np.array_equal(support.positions(obj.data), refined) and not obj.data.has_custom_normals
          and np.abs(refined - limit).max() > 1e-2,
          "use_limit_surface=False: the refined control points, no custom normals (as before)")
    support.remove(obj)


# --- limit normals ---------------------------------------------------------------------------------------------------

def creased_cube_normals():
    """A cube cut 2x2 per side with its 12 sides creased: the crease curves are straight and each side stays flat, so
    each side's normal at every corner of its faces is that side's plane normal (the hand check of the issue): across
    a crease the two sides' normals differ, and inside a side every corner of a vertex has the same one."""
    for rules in ('OPENSUBDIV', 'HOPPE94'):
        obj = support.shade_smooth(support.creased_cube(compat)[0])
        obj.name = f"CreasedCube{rules}"
        result, output = run_apply(obj, levels=2, rules=rules)
        mesh = obj.data
        normals = corner_normals(mesh)
        positions = support.positions(mesh)
        triangles = loop_vertices(mesh).reshape(-1, 3)
        centres = positions[triangles].mean(axis=1)
        axis = np.argmax(np.abs(centres), axis=1)  # the side each face lies on
        planes = np.zeros_like(centres)
        planes[np.arange(len(centres)), axis] = np.sign(centres[np.arange(len(centres)), axis])
        error = np.abs(normals - planes[:, None, :]).max()
        check(result == {'FINISHED'} and error < NORMAL_TOLERANCE,
              f"{rules}: every corner's normal is the plane normal of its side of the creased cube "
              f"(max difference {error:.1e})")
        spread = vertex_spread(mesh)
        creased = np.zeros(len(positions), dtype=bool)
        weights = compat.read_edge_creases(mesh)
        creased[support.edges(mesh)[weights >= 1.0].ravel()] = True
        check(spread[creased].min() > 0.5 and spread[~creased].max() < NORMAL_TOLERANCE,
              f"{rules}: on the {creased.sum()} crease vertices the sides' normals differ (by at least "
              f"{spread[creased].min():.2f}); the corners of the other {(~creased).sum()} vertices agree (within "
              f"{spread[~creased].max():.1e})")
        check("shaded smooth" not in output and "flat" not in output,
              f"{rules}: Apply has nothing to say about shading")
        support.remove(obj)


def flat_faces():
    """Flat faces stay flat with Use Limit Surface on, as in Subdivision Surface (whose result keeps each face's
    flat/smooth shading): the children of the cage's flat faces are flat and shade with their face normals, those of
    its smooth faces show the limit normals; Apply and the modifier alike, and no note about shading."""
    obj = support.object_from_bmesh("HalfFlat", support.cube("HalfFlat", subdivisions=1))
    cage_smooth = np.arange(len(obj.data.polygons)) % 2 == 0
    obj.data.polygons.foreach_set("use_smooth", cage_smooth)
    subsurf = support.copy_object(obj, "HalfFlat subsurf")
    reference = support.blender_subdivision(subsurf, 2, use_limit_surface=True)
    reference_smooth = support.read_array(reference.polygons, "use_smooth", dtype=bool)
    support.select_only(obj)
    mesh = obj.data
    mesh.calc_loop_triangles()
    triangles = support.read_array(mesh.loop_triangles, "vertices", 3, np.int32)
    cage = support.positions(mesh)
    _, limit_normals = core().Plan(triangles, len(cage), 2, rules="opensubdiv",
                                   limit_surface=True).evaluate_with_normals(cage)
    twin = support.copy_object(obj, "HalfFlat live")
    support.select_only(twin)
    bpy.ops.object.loop_subdivision_add(levels=2, rules='OPENSUBDIV')
    shown = twin.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    shown_smooth = support.read_array(shown.polygons, "use_smooth", dtype=bool)
    shown_normals = corner_normals(shown)
    result, output = run_apply(obj, levels=2, rules='OPENSUBDIV')
    smooth = support.read_array(obj.data.polygons, "use_smooth", dtype=bool)
    normals = corner_normals(obj.data)
    face_normals = support.read_array(obj.data.polygons, "normal", 3)
    check(result == {'FINISHED'} and smooth.any() and not smooth.all()
          and np.count_nonzero(smooth) * len(reference_smooth) == np.count_nonzero(reference_smooth) * len(smooth)
          and np.array_equal(shown_smooth, smooth),
          f"the children of flat faces are flat, of smooth faces smooth ({np.count_nonzero(~smooth)} of "
          f"{len(smooth)} flat; Subdivision Surface: {np.count_nonzero(~reference_smooth)} of "
          f"{len(reference_smooth)}), Apply and the modifier alike")
    flat_error = np.abs(normals[~smooth] - face_normals[~smooth][:, None, :]).max()
    smooth_error = np.abs(normals[smooth] - limit_normals[smooth]).max()
    check(flat_error < NORMAL_TOLERANCE and smooth_error < NORMAL_TOLERANCE,
          f"flat faces shade with their face normals (within {flat_error:.1e}), smooth ones with the limit normals "
          f"(within {smooth_error:.1e})")
    live_error = np.abs(shown_normals - normals).max()
    check(live_error < 1e-6, f"the modifier shows Apply's normals (within {live_error:.1e})")
    check("flat" not in output and "shaded smooth" not in output, "no note about shading")
    for other in (obj, twin, subsurf):
        support.remove(other)


def ringed_sphere_normals():
    """A sphere with a creased equator: the normals split along the equator only, and are the core's limit normals."""
    obj = support.object_from_bmesh("RingedSphere", support.uv_sphere(12, 8))
    p = support.positions(obj.data)
    e = support.edges(obj.data)
    ring = np.abs(p[:, 2]) < 1e-6
    support.set_edge_creases(obj.data, np.flatnonzero(ring[e[:, 0]] & ring[e[:, 1]]), 1.0, compat)
    obj.data.polygons.foreach_set("use_smooth", np.ones(len(obj.data.polygons), dtype=bool))
    _, output = run_apply(obj, levels=2, rules='OPENSUBDIV')
    mesh = obj.data
    positions = support.positions(mesh)
    spread = vertex_spread(mesh)
    equator = np.abs(positions[:, 2]) < 1e-6
    check(equator.sum() == 12 * 4 and spread[equator].min() > 0.1 and spread[~equator].max() < NORMAL_TOLERANCE,
          f"the normals split on the {equator.sum()} equator vertices only (by at least {spread[equator].min():.2f}; "
          f"elsewhere within {spread[~equator].max():.1e})")
    normals = corner_normals(mesh)
    side = np.sign(positions[loop_vertices(mesh).reshape(-1, 3)].mean(axis=1)[:, 2])
    at_equator = equator[loop_vertices(mesh)].reshape(-1, 3)
    # On the equator each side's normal leans towards its own pole.
    leaning = (normals[..., 2] * side[:, None])[at_equator]
    check(leaning.min() > 0.05, f"on the equator each side's normal leans towards its hemisphere's pole "
                                f"(z component at least {leaning.min():.2f} that way)")
    check("flat-shaded" not in output, "a mesh shaded smooth already gets no note about shading")
    support.remove(obj)


def sharp_edges_kept():
    """A marked sharp edge, with Auto Smooth on (3.x), still shows: the result's corners on its child edges keep
    Blender's own split normals, so the two sides of it differ."""
    obj = support.object_from_bmesh("SharpEdge", support.uv_sphere(12, 8))
    mesh = obj.data
    mesh.polygons.foreach_set("use_smooth", np.ones(len(mesh.polygons), dtype=bool))
    compat.shade_sharp_edges(mesh)  # Auto Smooth at 180 degrees up to 4.0: the marks alone split the shading
    p = support.positions(mesh)
    e = support.edges(mesh)
    ring = np.flatnonzero((np.abs(p[e[:, 0], 2]) < 1e-6) & (np.abs(p[e[:, 1], 2]) < 1e-6))
    sharp = np.zeros(len(e), dtype=bool)
    sharp[ring] = True
    mesh.edges.foreach_set("use_edge_sharp", sharp)
    run_apply(obj, levels=1, rules='OPENSUBDIV')
    mesh = obj.data
    spread = vertex_spread(mesh)
    sharp = support.read_array(mesh.edges, "use_edge_sharp", dtype=bool)
    on_sharp = np.zeros(len(mesh.vertices), dtype=bool)
    on_sharp[support.edges(mesh)[sharp].ravel()] = True
    check(sharp.sum() == 2 * len(ring) and spread[on_sharp].min() > 0.05 and spread[~on_sharp].max() < NORMAL_TOLERANCE,
          f"the equator's {len(ring)} marked sharp edges (now {sharp.sum()}) still split the normals (by at least "
          f"{spread[on_sharp].min():.2f}); elsewhere they are shared (within {spread[~on_sharp].max():.1e})")
    # Blender's own there: what it shades the same mesh with when no corner has a custom normal (a zero vector keeps
    # Blender's own, in every version; free normals, 4.5+, would hide it).
    own = mesh.copy()
    free = own.attributes.get("custom_normal")
    if free is not None and free.data_type == 'FLOAT_VECTOR':
        own.attributes.remove(free)
    own.normals_split_custom_set(np.zeros((len(own.loops), 3), dtype=np.float32))
    corners = on_sharp[support.read_array(mesh.loops, "vertex_index", dtype=np.int32)]
    difference = np.abs(compat.read_corner_normals(mesh) - compat.read_corner_normals(own))[corners].max()
    check(difference < 1e-5, f"the corners on them shade with Blender's own normals (within {difference:.1e})")
    bpy.data.meshes.remove(own)
    support.remove(obj)


# --- custom normals the mesh had --------------------------------------------------------------------------------

def custom_normals_carried():
    for limit in (True, False):
        obj = support.object_from_bmesh(f"Custom{limit}", support.cube("Custom", subdivisions=1))
        mesh = obj.data
        if hasattr(mesh, "use_auto_smooth"):
            mesh.use_auto_smooth = True
        tilted = np.tile(np.array([0.0, 0.6, 0.8], np.float32), (len(mesh.loops), 1))
        mesh.normals_split_custom_set(tilted)
        result, output = run_apply(obj, levels=2, rules='OPENSUBDIV', use_limit_surface=limit)
        error = np.abs(compat.read_corner_normals(obj.data) - tilted[:1]).max()
        # What Blender's storage keeps of that constant field on this very mesh (measured: up to 1e-2 where the
        # field points away from a face's own normal).
        direct = obj.data.copy()
        direct.normals_split_custom_set(np.tile(tilted[:1], (len(direct.loops), 1)))
        storage = np.abs(compat.read_corner_normals(direct) - tilted[:1]).max()
        bpy.data.meshes.remove(direct)
        check(result == {'FINISHED'} and obj.data.has_custom_normals and error <= storage + 1e-5,
              f"limit {'on' if limit else 'off'}: custom normals are carried over, interpolated (a constant field "
              f"stays that constant within {error:.1e}; Blender's storage of it: {storage:.1e})")
        if limit:
            check("custom split normals are carried over" in output,
                  "limit on: Apply says the custom normals take the place of the limit normals")
        support.remove(obj)
    if hasattr(bpy.types.Mesh, "use_auto_smooth"):
        obj = support.object_from_bmesh("CustomUnused", support.cube("CustomUnused"))
        obj.data.use_auto_smooth = True
        obj.data.normals_split_custom_set(np.tile([0.0, 0.0, 1.0], (len(obj.data.loops), 1)))
        obj.data.use_auto_smooth = False
        result, output = run_apply(obj, levels=1, rules='OPENSUBDIV')
        check(result == {'FINISHED'} and "custom split normals are not carried over" in output,
              "Blender 3.x, Auto Smooth off: custom normals that do not shade are dropped with a warning")
        support.remove(obj)


# --- Suzanne as an artist makes it ------------------------------------------------------------------------------------

def suzanne():
    """Add ▸ Monkey (with its UV map), Ctrl T in Edit Mode (Beauty), then Apply with the defaults: limit surface and
    Keep Boundaries UVs. (test_apply subdivides bmesh's Suzanne triangulated with Beauty, which has two faces on the
    same three vertices; Ctrl T on Blender 3.4.1's Add ▸ Monkey makes none.)"""
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.object
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.select_all(action='SELECT')
    bpy.ops.mesh.quads_convert_to_tris(quad_method='BEAUTY', ngon_method='BEAUTY')
    bpy.ops.object.mode_set(mode='OBJECT')
    faces = len(obj.data.polygons)
    result, output = run_apply(obj, levels=2)
    mesh = obj.data
    uvs = support.read_array(mesh.uv_layers.active.data, "uv", 2)
    lengths = np.linalg.norm(compat.read_corner_normals(mesh), axis=1)
    check(result == {'FINISHED'} and len(mesh.polygons) == 16 * faces
          and np.isfinite(support.positions(mesh)).all() and np.isfinite(uvs).all()
          and np.abs(lengths - 1).max() < 1e-3 and not mesh.validate(verbose=True),
          f"a Beauty-triangulated Suzanne ({faces} faces) applies with the defaults: {len(mesh.polygons)} faces, "
          "finite positions and UVs, unit normals, a valid mesh")
    support.remove(obj)
    for rules in ('OPENSUBDIV', 'HOPPE94'):
        bpy.ops.mesh.primitive_monkey_add()
        obj = bpy.context.object
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.quads_convert_to_tris(quad_method='BEAUTY', ngon_method='BEAUTY')
        bpy.ops.object.mode_set(mode='OBJECT')
        result, _ = run_apply(obj, levels=1, rules=rules, uv_smooth='SMOOTH_ALL')
        check(result == {'FINISHED'}, f"{rules}, UV Smooth All: the triangulated Suzanne applies")
        support.remove(obj)


# --- the modifier ---------------------------------------------------------------------------------------------------

def modifier_settings():
    """The live entry honours both settings: each change builds a new plan and shows what Apply writes."""
    bm = bmesh.new()
    bm.loops.layers.uv.new("UVMap")
    bmesh.ops.create_cube(bm, size=2.0, calc_uvs=True)
    obj = support.shade_smooth(support.object_from_bmesh("Live", bm))
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(levels=1, rules='OPENSUBDIV')
    settings = obj.loop_subdivision
    for name, value in (("use_limit_surface", False), ("uv_smooth", 'SMOOTH_ALL'), ("use_limit_surface", True)):
        builds = addon.live.engine.cache_of(obj).plan_builds
        setattr(settings, name, value)
        mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        shown = (support.positions(mesh), support.read_array(mesh.uv_layers["UVMap"].data, "uv", 2),
                 mesh.has_custom_normals)
        twin = support.copy_object(obj, "Live twin")
        twin.modifiers.clear()
        support.apply_loop(twin)  # the object's settings
        expected = (support.positions(twin.data), support.read_array(twin.data.uv_layers["UVMap"].data, "uv", 2),
                    twin.data.has_custom_normals)
        support.remove(twin)
        support.select_only(obj)
        check(addon.live.engine.cache_of(obj).plan_builds == builds + 1 and np.array_equal(shown[0], expected[0])
              and np.array_equal(shown[1], expected[1]) and shown[2] == expected[2] == settings.use_limit_surface,
              f"modifier: {name} = {value!r} builds a new plan and shows what Apply writes")
    support.remove(obj)



def semi_sharp_corners():
    """A cube with every edge creased 0.6 (sharpness 3.6, OpenSubdiv rules): with Use Limit Surface the corners are
    the limit surface's, which goes on refining until the sharpness is spent and then smooths them, as Subdivision
    Surface's does. So a corner lands where it lands at every level (a limit does not depend on the level it is taken
    from; before issue 23 levels 1-3 kept the corners at the crease limit (1, 1, 1) and level 4 moved them), and
    close to Subdivision Surface's (Catmull-Clark on the quads: not the same surface, the same behaviour)."""
    corners = {}
    for levels in (1, 2, 3, 4):
        obj = support.object_from_bmesh(f"SemiSharp{levels}", support.cube(f"SemiSharp{levels}"), triangulate=False)
        support.set_edge_creases(obj.data, np.arange(len(obj.data.edges)), 0.6, compat)
        cage = support.positions(obj.data)
        blender = support.blender_subdivision(obj, levels, use_limit_surface=True)
        theirs = support.positions(blender)
        bpy.data.meshes.remove(blender)
        result, _ = run_apply(obj, levels=levels, rules='OPENSUBDIV', use_limit_surface=True)
        ours = support.positions(obj.data)
        # The cage's vertices keep their indices at every level.
        corners[levels] = ours[:len(cage)]
        nearest = np.linalg.norm(theirs[None, :, :] - corners[levels][:, None, :], axis=2).min(axis=1)
        check(result == {'FINISHED'} and np.abs(corners[levels]).max() < 0.99 and nearest.max() < 0.03,
              f"level {levels}: the corners move in from (1, 1, 1) to the limit surface, within {nearest.max():.3f} "
              "of Subdivision Surface's (cube of side 2)")
        support.remove(obj)
    spread = max(np.abs(corners[levels] - corners[1]).max() for levels in corners)
    check(spread < 1e-5, f"the corners' limit positions are the same at levels 1-4 (within {spread:.1e})")


support.clear_scene()
settings_as_blender()
script_call()
flat_faces()
creased_cube_normals()
ringed_sphere_normals()
semi_sharp_corners()
sharp_edges_kept()
custom_normals_carried()
suzanne()
modifier_settings()
addon.unregister()
check.finish()
