"""What a saved file holds with the Loop Subdivision modifier, against the same file with Blender's Subdivision
Surface; and Blender's own Apply of an entry that is not first.

- By default a file holds the cage and the settings: it is at most 1.2 times the size of the same file with
  Subdivision Surface in place of the entry, and opening it (the add-on enabled) makes the same result again.
- With Adaptive Subdivision on, the same: at most 1.2 times the size of the Subdivision Surface file, and the same cut
  made again on opening (the scene camera's).
- Store Result keeps the Render-level result in the file; the panel's estimate of what that costs is within a third
  of what the file grows by.
- The add-on turned off in a session: its entries show their input, and a save stays lean; turned on again, they
  are live.
- An object with an entry linked into another file shows the result its file stored (Store Result), or its input,
  the panel saying why and what to do.
- A file saved by the add-on's first layout of the node group (the helper's mesh alone) opens with the current one.
- Blender's own Apply of an entry under an Array, a Mirror or a Displace gives what Subdivision Surface's gives in
  the same place and what the panel's Apply gives: the object's own mesh subdivided, the modifier above left in the
  stack; never the result of the stack baked into the mesh under it.
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bmesh  # noqa: E402
import bpy  # noqa: E402
import numpy as np  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_files")
stack, ui, compat = addon.blender.stack, addon.ui.panel, support.blender_access(addon)


def evaluated(obj):
    mesh = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
    return support.positions(mesh), len(mesh.polygons)


def sphere(name):
    """A UV-mapped icosphere of 1,280 triangles, shaded smooth, as an artist starts from."""
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=4, radius=1.0)
    obj = bpy.context.object
    obj.name = name
    return support.shade_smooth(obj)


def saved_size(folder, name):
    path = os.path.join(folder, name + ".blend")
    bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
    return path, os.path.getsize(path)


def thumbnail(*_):
    bpy.context.view_layer.update()


def saved_as_from_the_interface(folder, name):
    """saved_size, with the scene evaluated again after the save handlers: the interface draws the file's thumbnail
    then."""
    bpy.app.handlers.save_pre.append(thumbnail)
    try:
        return saved_size(folder, name)
    finally:
        bpy.app.handlers.save_pre.remove(thumbnail)


def subsurf_size(folder, obj, name):
    """The size of the file with a level-3 Subdivision Surface on obj, which is taken off again."""
    subsurf = obj.modifiers.new("Subdivision", 'SUBSURF')
    subsurf.levels, subsurf.render_levels = 3, 3
    _, size = saved_size(folder, name)
    obj.modifiers.remove(subsurf)
    return size


def file_sizes(folder):
    support.clear_scene()
    obj = sphere("Subdivided")
    reference = subsurf_size(folder, obj, "subsurf")
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(levels=3, render_levels=3)
    positions, faces = evaluated(obj)
    path, lean = saved_as_from_the_interface(folder, "lean")
    check(lean <= 1.2 * reference,
          f"by default the file is {lean / reference:.2f}x the size of the same file with Subdivision Surface "
          f"({lean} against {reference} bytes; at most 1.2x)")
    check(np.array_equal(evaluated(obj)[0], positions), "after saving, the result is shown again")

    obj.loop_subdivision.store_result = True
    estimate = ui.stored_bytes(obj, stack.entry(obj))
    _, stored = saved_size(folder, "stored")
    grown = stored - lean
    check(abs(estimate - grown) <= grown / 3,
          f"Store Result: the file grows by {grown / 1e6:.1f} MB, the panel says about {estimate / 1e6:.1f} MB")

    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Subdivided"]
    reopened, reopened_faces = evaluated(obj)
    check(reopened_faces == faces and np.array_equal(reopened, positions),
          f"the file opened with the add-on shows the same result, made again ({reopened_faces} faces)")
    check(not any(other.get(stack.PLACEHOLDER_TAG) for other in bpy.data.objects),
          "nothing of the saving stays in the opened file")


def turned_off_and_on(folder):
    """The add-on turned off in a session with an entry (Preferences ▸ Add-ons, or an extension updated): the entry
    shows its input as a Blender without the add-on does, following edits of the cage, and a save stays as lean as
    with the add-on on; turned on again, the result is back, made from the edited cage."""
    support.clear_scene()
    obj = sphere("Switched")
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(levels=2)
    _, lean = saved_size(folder, "switched_on")
    cage = len(obj.data.polygons)
    addon.unregister()
    try:
        for vertex in obj.data.vertices:
            vertex.co *= 2.0
        obj.data.update()
        positions, faces = evaluated(obj)
        check(faces == cage and abs(np.linalg.norm(positions, axis=1).max() - 2.0) < 1e-5,
              f"turned off: the entry shows its input, as edited ({faces} faces)")
        _, off = saved_size(folder, "switched_off")
        check(off <= 1.05 * lean, f"turned off, a save is as lean as with the add-on on ({off} against {lean} bytes)")
    finally:
        addon.register()
    positions, faces = evaluated(obj)
    check(faces == 16 * cage and np.linalg.norm(positions, axis=1).max() > 1.5,
          f"turned on again: the result of the edited cage ({faces} faces)")


def linked(folder):
    """An object with an entry, linked into another file (File ▸ Link, as an asset is): with Store Result in its own
    file it shows that result; by default that file keeps none, and it shows its input, the panel and the console
    saying why and what to do."""
    for store in (False, True):
        support.clear_scene()
        obj = sphere("Prop")
        support.select_only(obj)
        bpy.ops.object.loop_subdivision_add(levels=1, render_levels=1)
        obj.loop_subdivision.store_result = store
        asset = os.path.join(folder, f"asset_{store}.blend")
        bpy.ops.wm.save_as_mainfile(filepath=asset, copy=True)
        support.clear_scene()
        with bpy.data.libraries.load(asset, link=True) as (_, into):
            into.objects = ["Prop"]
        prop = into.objects[0]
        bpy.context.scene.collection.objects.link(prop)
        bpy.context.view_layer.update()
        faces = evaluated(prop)[1]
        cage = len(prop.data.polygons)
        cache = addon.live.engine.cache_of(prop)
        error = cache.error if cache is not None else ""
        if store:
            check(faces == 4 * cage and not error, f"linked with Store Result: the stored result shows ({faces} faces)")
        else:
            check(faces == cage and "Store Result" in error and "Library Override" in error,
                  f"linked without a stored result: the input shows ({faces} faces), the panel says why ({error!r})")
        bpy.data.objects.remove(prop)
        bpy.data.libraries.remove(bpy.data.libraries[-1])


def adaptive_file_size(folder):
    """The result of Adaptive Subdivision (finer here than level 3) is made again on opening, never stored: the file
    is the cage's and the settings'."""
    support.clear_scene()
    support.tiny_render_camera(4.0)
    obj = sphere("Adaptive")
    reference = subsurf_size(folder, obj, "adaptive-subsurf")
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=0.02)
    positions, faces = evaluated(obj)
    path, size = saved_as_from_the_interface(folder, "adaptive")
    check(faces > 4 ** 3 * len(obj.data.polygons) and size <= 1.2 * reference,
          f"Adaptive Subdivision ({faces} triangles): the file is {size / reference:.2f}x the size of the same file "
          f"with Subdivision Surface at level 3 ({size} against {reference} bytes; at most 1.2x)")
    bpy.ops.wm.open_mainfile(filepath=path)
    reopened, reopened_faces = evaluated(bpy.data.objects["Adaptive"])
    check(reopened_faces == faces and np.array_equal(reopened, positions),
          f"the file opened with the add-on shows the same adaptive cut, made again ({reopened_faces} faces)")


def first_layout(folder):
    """The node group as the add-on's first version made it: the helper's mesh, straight to the output."""
    support.clear_scene()
    obj = sphere("Old")
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(levels=1)
    positions, faces = evaluated(obj)
    group = stack.entry(obj).node_group
    group.nodes.clear()
    group_input, info, group_output = (group.nodes.new(kind) for kind in
                                       ('NodeGroupInput', 'GeometryNodeObjectInfo', 'NodeGroupOutput'))
    info.transform_space = 'ORIGINAL'
    group.links.new(group_input.outputs[stack.RESULT_SOCKET], info.inputs["Object"])
    group.links.new(info.outputs["Geometry"], group_output.inputs["Geometry"])
    group[stack.GROUP_TAG] = 1
    path = os.path.join(folder, "first-layout.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
    bpy.ops.wm.open_mainfile(filepath=path)
    obj = bpy.data.objects["Old"]
    reopened, reopened_faces = evaluated(obj)
    check(stack.entry(obj).node_group.get(stack.GROUP_TAG) == stack.GROUP_VERSION
          and reopened_faces == faces and np.allclose(reopened, positions, atol=1e-6),
          "a file with the first layout of the node group opens with the current one and the same result")


def under(kind, name, grouped=False):
    """A UV-mapped, smooth Suzanne (500 faces) with a modifier of this kind above where the entry or Subdivision
    Surface goes: an Array (more faces), a Mirror (every face twice) or a Displace (the same vertices elsewhere)."""
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.object
    obj.name = obj.data.name = name
    if grouped:
        obj.vertex_groups.new(name="Weights").add(range(len(obj.data.vertices)), 0.5, 'REPLACE')
    above = obj.modifiers.new(kind.title(), kind)
    if kind == 'DISPLACE':
        above.strength = 0.3
    support.select_only(obj)
    return obj


def blender_apply_of(obj, modifier):
    """Blender's own Apply (the modifier's menu ▸ Apply, Ctrl A over its panel): its result or its refusal."""
    try:
        with bpy.context.temp_override(object=obj, active_object=obj):
            return bpy.ops.object.modifier_apply(modifier=modifier.name)
    except RuntimeError as error:
        return str(error)


def not_first(kind, levels, grouped=False):
    """Blender's own Apply of an entry under a modifier of this kind, against the panel's Apply and Subdivision
    Surface's Apply in the same place: the object's own mesh subdivided, the modifier above left in the stack."""
    what = f"under {kind.title()}, level {levels}" + (", the cage with a vertex group" if grouped else "")
    support.clear_scene()
    alone = under(kind, "Alone", grouped)
    alone.modifiers.clear()
    alone.modifiers.new("Subdivision", 'SUBSURF').levels = levels
    alone_faces = evaluated(alone)[1]
    reference = under(kind, "Subsurf", grouped)
    subsurf = reference.modifiers.new("Subdivision", 'SUBSURF')
    subsurf.levels = levels
    result = blender_apply_of(reference, subsurf)
    check(result == {'FINISHED'} and [m.type for m in reference.modifiers] == [kind]
          and len(reference.data.polygons) == alone_faces,
          f"{what}: Subdivision Surface's Apply subdivides the object's own mesh, as it would alone, and leaves the "
          f"{kind.title()} ({len(reference.data.polygons)} faces)")

    copies = MADE_BY[kind]
    obj = under(kind, "Blender", grouped)
    printed = support.raised_in_handlers(lambda: (bpy.ops.object.loop_subdivision_add(levels=levels), evaluated(obj)))
    check("Error" not in printed,
          f"{what}: adding the entry raises nothing in Blender's handlers ({printed.strip()!r})")
    stacked_faces = evaluated(obj)[1]
    panel = under(kind, "Panel", grouped)
    bpy.ops.object.loop_subdivision_add(levels=levels)
    triangles = sum(len(face.vertices) - 2 for face in obj.data.polygons)
    check(stacked_faces == copies * triangles * 4 ** levels,
          f"{what}: the entry shows the subdivision of what the {kind.title()} makes ({stacked_faces} faces)")
    result = blender_apply_of(obj, stack.entry(obj))
    support.select_only(panel)
    applied = support.capture_output(lambda: bpy.ops.object.loop_subdivision_apply())[0]
    ours, theirs = support.positions(obj.data), support.positions(panel.data)
    diagonal = float(np.linalg.norm(theirs.max(axis=0) - theirs.min(axis=0)))
    check(result == {'FINISHED'} and applied == {'FINISHED'} and [m.type for m in obj.modifiers] == [kind]
          and len(ours) == len(theirs) and len(obj.data.polygons) == len(panel.data.polygons)
          and np.abs(ours - theirs).max() <= 1e-5 * diagonal,
          f"{what}: Blender's Apply gives the panel's Apply, the object's own mesh subdivided, the {kind.title()} "
          f"left above ({result}; {len(ours)} vertices against {len(theirs)}, "
          f"{np.abs(ours - theirs).max() / diagonal if len(ours) == len(theirs) else float('nan'):.1e} of the "
          "diagonal)")
    check(stack.BASE_INPUT_ATTRIBUTE not in obj.data.attributes,
          f"{what}: the mark of the Base Result does not go into the mesh")
    check(evaluated(obj)[1] == copies * len(obj.data.polygons),
          f"{what}: after the Apply the {kind.title()} acts on the subdivided mesh, once")


MADE_BY = {'ARRAY': 2, 'MIRROR': 2, 'DISPLACE': 1}  # copies of the mesh a modifier of this kind makes (defaults)


def base_results_in_a_session(folder):
    """Entries that are not first (each keeps a Base Result) among others, through what a session does with them: a
    save, the add-on turned off and on, Edit Mode; and modifiers above that leave the vertices where they are."""
    support.clear_scene()
    names = ("A_first", "M_array", "Z_last")  # the entry under the Array between two that are first, by name
    for name in names:
        obj = under('ARRAY', name) if name == "M_array" else sphere(name)
        support.select_only(obj)
        bpy.ops.object.loop_subdivision_add(levels=1)
    shown = {name: evaluated(bpy.data.objects[name])[1] for name in names}
    path = os.path.join(folder, "bases.blend")
    printed = support.raised_in_handlers(lambda: bpy.ops.wm.save_as_mainfile(filepath=path, copy=True))
    with bpy.data.libraries.load(path) as (data_from, _):
        results = [name for name in data_from.meshes if name.endswith(("(Loop Subdivision)", "(Base Result)"))]
    check("Error" not in printed and not results,
          f"a save with an entry that is not first raises nothing and writes no result ({printed.strip()!r}; "
          f"{results})")
    try:
        addon.unregister()
        unregistered = ""
    except Exception as error:  # noqa: BLE001  (what the artist would see in Preferences)
        unregistered = repr(error)
    cages = {name: evaluated(bpy.data.objects[name])[1] for name in names}
    addon.register()
    check(not unregistered and all(cages[name] < shown[name] for name in names),
          f"turned off, every entry shows its input ({cages}; {unregistered})")
    back = {name: evaluated(bpy.data.objects[name])[1] for name in names}
    check(back == shown, f"turned on again, every entry shows its result ({back})")

    obj = bpy.data.objects["M_array"]
    before, _ = evaluated(obj)
    support.select_only(obj)
    bpy.ops.object.mode_set(mode='EDIT')
    edited = bmesh.from_edit_mesh(obj.data)
    for vertex in edited.verts:
        vertex.co.z += 0.25
    bmesh.update_edit_mesh(obj.data)
    printed = support.raised_in_handlers(lambda: evaluated(obj))
    after, _ = evaluated(obj)
    bpy.ops.object.mode_set(mode='OBJECT')
    check("Error" not in printed and abs((after - before)[:, 2].mean() - 0.25) < 1e-4,
          f"in Edit Mode the entry under the Array follows the edit, with no error ({printed.strip()!r})")

    # Above the entry, a Displace of no strength and a Triangulate move no vertex: the result of the stack shows (at
    # Render levels in renders), not the Base Result.
    rest = under('DISPLACE', "Rest")
    rest.modifiers[0].strength = 0.0
    bpy.ops.object.loop_subdivision_add(levels=1, render_levels=2)
    addon.live.engine.refresh_all(render=True)  # what each frame of a render does
    triangles = sum(len(face.vertices) - 2 for face in rest.data.polygons)
    rendered = evaluated(rest)[1]
    addon.live.engine.refresh_all()
    check(rendered == 16 * triangles, f"a rest state above: a render shows Render levels ({rendered} faces)")
    for method in ('BEAUTY', 'SHORTEST_DIAGONAL'):
        stacked = under('TRIANGULATE', f"Triangulated{method}")
        stacked.modifiers[0].quad_method = method
        bpy.ops.object.loop_subdivision_add(levels=1)
        applied = under('TRIANGULATE', f"Applied{method}")
        applied.modifiers[0].quad_method = method
        with bpy.context.temp_override(object=applied, active_object=applied):
            bpy.ops.object.modifier_apply(modifier=applied.modifiers[0].name)
        bpy.ops.object.loop_subdivision_add(levels=1)
        ours, theirs = evaluated(stacked)[0], evaluated(applied)[0]
        check(ours.shape == theirs.shape and np.abs(ours - theirs).max() < 1e-6,
              f"a Triangulate above ({method}): the entry shows the result of the stack, as with the Triangulate "
              "applied")


def blender_apply_not_first():
    not_first('ARRAY', 1)
    not_first('MIRROR', 2, grouped=True)
    not_first('DISPLACE', 1)  # as many vertices as the mesh: told apart by where they are
    # With the modifier above off in the viewport the entry acts first, and Blender's Apply bakes its result.
    support.clear_scene()
    obj = sphere("MirrorOff")
    obj.modifiers.new("Mirror", 'MIRROR').show_viewport = False
    support.select_only(obj)
    bpy.ops.object.loop_subdivision_add(levels=1)
    positions, faces = evaluated(obj)
    check(compat.modifier_input(stack.entry(obj), stack.BASE_SOCKET) is None,
          "an entry that acts first keeps no Base Result")
    result = blender_apply_of(obj, stack.entry(obj))
    check(result == {'FINISHED'} and len(obj.data.polygons) == faces
          and np.array_equal(support.positions(obj.data), positions),
          "with the modifiers above off, Blender's Apply writes the result into the mesh")


with tempfile.TemporaryDirectory() as folder:
    file_sizes(folder)
    turned_off_and_on(folder)
    linked(folder)
    adaptive_file_size(folder)
    first_layout(folder)
    base_results_in_a_session(folder)
blender_apply_not_first()
addon.unregister()
check.finish()
