"""The data the Loop Subdivision modifier leaves in a file, against what Blender's own Subdivision Surface leaves after
the same steps: cycles of adding, removing and re-adding the entry, Shift D and Alt D copies, a tiny Cycles render,
deleting the Alt D copy and applying the original (Blender's Apply refuses a mesh that a deleted copy still shares),
deleting the Shift D copy, then saving and reopening the file. Our entry runs the cycles twice: by levels, and with
Adaptive Subdivision on (its result is made the same way, and must leave no more behind). And Ctrl C / Ctrl V of an
object with an entry into another file.

After each cycle (before saving, and after reopening) every bpy.data collection holds as many IDs as with Subdivision
Surface, except that the add-on may have one helper object, one result mesh and one node group more per live entry;
the objects and meshes the artist sees (in a scene, or orphan meshes) are exactly as many, and the IDs without users
(orphan data) are the same in number per collection: none after reopening. The expected values are Blender's, measured
by running the same steps with Subdivision Surface; the add-on's code is not asked what it keeps.

Also: a file saved by the add-on's earlier versions, whose helpers held their owner as an ID pointer (a user: a deleted
object, and a deleted linked duplicate with it, stayed in the file), opens with the deleted objects freed and Apply
working. In Debian's Blender 3.4.1 each cycle also undoes and redoes the deletion of the Shift D copy (not in the bpy
wheels, where undo may not work).
"""
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
check = support.Check("test_lifecycle")
CYCLES = 4
# Undo steps only in Blender the program: the bpy wheels may not run them as the interface does.
UNDO = bool(bpy.app.binary_path) and bpy.app.version < (4, 0, 0)
# Every ID collection of bpy.data; "all_ids" (5.2) is every ID at once, counted in the others.
COLLECTIONS = sorted(prop.identifier for prop in bpy.types.BlendData.bl_rna.properties
                     if prop.type == 'COLLECTION' and prop.identifier != "all_ids")


def update():
    bpy.context.view_layer.update()  # runs the depsgraph handlers, as the interface does after each step


def select(obj):
    support.select_only(obj)


# --- the kinds of entry: Blender's Subdivision Surface, and ours through its operators, by levels (LOOP) or cut for the
# scene camera (ADAPTIVE) ---------------------------------------------------------------------------------------------

def add_entry(kind, obj):
    select(obj)
    if kind == 'SUBSURF':
        modifier = obj.modifiers.new("Subdivision", 'SUBSURF')
        modifier.levels, modifier.render_levels = 1, 2
    elif kind == 'ADAPTIVE':
        assert bpy.ops.object.loop_subdivision_add(use_adaptive=True, dicing_rate=0.5) == {'FINISHED'}
    else:
        assert bpy.ops.object.loop_subdivision_add(levels=1, render_levels=2) == {'FINISHED'}


def remove_entry(kind, obj):
    select(obj)
    if kind == 'SUBSURF':
        obj.modifiers.remove(obj.modifiers[-1])
    else:
        assert bpy.ops.object.loop_subdivision_remove() == {'FINISHED'}


def has_entry(kind, obj):
    return any(modifier.type == 'SUBSURF' if kind == 'SUBSURF' else modifier.type == 'NODES'
               for modifier in obj.modifiers)


def duplicate(obj, linked):
    select(obj)
    assert bpy.ops.object.duplicate(linked=linked) == {'FINISHED'}
    copy = bpy.context.view_layer.objects.active
    assert copy != obj and (copy.data == obj.data) == linked
    return copy


def delete(obj):
    select(obj)
    assert bpy.ops.object.delete() == {'FINISHED'}


def blender_apply(obj):
    """Blender's own Apply of the object's last modifier (the entry): its result and what it printed (or the error
    it raised: "Modifiers cannot be applied to multi-user data")."""
    def apply():
        try:
            return bpy.ops.object.modifier_apply(modifier=obj.modifiers[-1].name)
        except RuntimeError as error:
            print(error)
            return {'CANCELLED'}
    with bpy.context.temp_override(object=obj, active_object=obj, selected_objects=[obj]):
        return support.capture_output(apply)


def render():
    bpy.ops.render.render()


rendered = []  # the faces of the watched object each render's depsgraph evaluated
watched = [None]


@bpy.app.handlers.persistent
def _record_render(scene, depsgraph):
    if depsgraph.mode == 'RENDER' and watched[0] in depsgraph.objects:
        obj = bpy.data.objects[watched[0]].evaluated_get(depsgraph)
        rendered.append(len(obj.data.polygons))


bpy.app.handlers.frame_change_post.append(_record_render)


def viewport_faces(obj):
    return len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)


def result_object(kind, obj):
    """The name of the object the entry's node group reads its result from (the add-on's helper)."""
    modifier = obj.modifiers[-1]
    return None if kind == 'SUBSURF' else addon.blender.stack.modifier_input(modifier, "Result").name


def save_and_reopen(path):
    assert bpy.ops.wm.save_as_mainfile(filepath=path) == {'FINISHED'}
    assert bpy.ops.wm.open_mainfile(filepath=path) == {'FINISHED'}
    update()


# --- what a file holds -----------------------------------------------------------------------------------------------

def snapshot(kind):
    """Counts of every bpy.data collection, of IDs without users per collection, of the objects and meshes the
    artist sees (objects in a scene; meshes they use, and orphan meshes), and of live entries."""
    counts = {name: len(getattr(bpy.data, name)) for name in COLLECTIONS}
    orphans = {name: sum(1 for block in getattr(bpy.data, name) if block.users == 0) for name in COLLECTIONS}
    in_scenes = [obj for obj in bpy.data.objects if obj.users_scene]
    seen_meshes = {obj.data.name_full for obj in in_scenes if obj.type == 'MESH'}
    seen_meshes |= {mesh.name_full for mesh in bpy.data.meshes if mesh.users == 0}
    return {"counts": counts, "orphans": {name: n for name, n in orphans.items() if n},
            "visible_objects": len(in_scenes), "visible_meshes": len(seen_meshes),
            "live": sum(1 for obj in in_scenes if has_entry(kind, obj))}


def base_file(folder):
    """An empty scene with a camera, rendering 16x16 pixels with one Cycles sample."""
    support.clear_scene()
    support.tiny_render_camera(8.0)
    path = os.path.join(folder, "base.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)
    return path


def run(kind, base, folder):
    """The cycles with one kind of entry; returns [(cycle, "saved"|"reopened", snapshot)] and notes to check."""
    bpy.ops.wm.open_mainfile(filepath=base)
    update()
    path = os.path.join(folder, f"{kind.lower()}.blend")
    snapshots, notes = [], []
    for cycle in range(CYCLES):
        name = f"Cage{cycle}"
        obj = support.object_from_bmesh(name, support.cube(name))
        obj.location.x = 3.0 * cycle - 3.0
        add_entry(kind, obj)
        update()
        remove_entry(kind, obj)
        update()
        add_entry(kind, obj)  # re-added
        update()
        before = result_object(kind, obj)
        remove_entry(kind, obj)
        add_entry(kind, obj)  # removed and re-added within one step
        update()
        if kind != 'SUBSURF':
            notes.append((cycle, f"re-added, the entry reuses the object's helper ({before})",
                          result_object(kind, obj) == before == f"{name} (Loop Subdivision)"))
        shift_d = duplicate(obj, linked=False)
        update()
        alt_d = duplicate(obj, linked=True)
        update()
        rendered.clear()
        watched[0] = name
        render()
        update()
        render()
        update()
        if kind == 'LOOP':
            cage = len(obj.data.polygons)
            notes.append((cycle, f"renders show Render levels ({rendered}), the viewport Levels Viewport after",
                          rendered.count(16 * cage) == 2 and viewport_faces(obj) == 4 * cage))
        elif kind == 'ADAPTIVE':  # the render's dicing rate (1 px) is coarser than the viewport's (0.5 px) here
            shown = viewport_faces(obj)
            notes.append((cycle, f"renders show the render's cut ({rendered}), the viewport its own after ({shown})",
                          len(rendered) == 2 and rendered[0] == rendered[1] and 2 * len(obj.data.polygons)
                          < rendered[0] < shown))
        delete(alt_d)
        update()
        notes.append((cycle, "the Alt D copy deleted, the original's mesh has one user", obj.data.users == 1))
        if cycle % 2 == 0:  # Blender's Apply, then the entry again
            result, output = blender_apply(obj)
            notes.append((cycle, f"Blender's Apply after Alt D and deleting the copy: {result} {output.strip()!r}",
                          result == {'FINISHED'} and not has_entry(kind, obj)))
            if not has_entry(kind, obj):
                add_entry(kind, obj)
            update()
        if UNDO:  # the Shift D copy deleted, undone and redone, as a click would push the steps
            copy_name = shift_d.name
            bpy.ops.ed.undo_push(message="before deleting the Shift D copy")
            select(shift_d)
            bpy.ops.object.delete('EXEC_DEFAULT', True)
            update()
            bpy.ops.ed.undo()
            update()
            restored = bpy.data.objects.get(copy_name)
            notes.append((cycle, "undo brings the deleted Shift D copy back, subdivided",
                          restored is not None and has_entry(kind, restored)
                          and viewport_faces(restored) > len(restored.data.polygons)))
            bpy.ops.ed.redo()
            update()
            notes.append((cycle, "redo deletes it again", bpy.data.objects.get(copy_name) is None))
            obj = bpy.data.objects[name]
        else:
            delete(shift_d)
        update()
        snapshots.append((cycle, "saved", snapshot(kind)))
        save_and_reopen(path)
        snapshots.append((cycle, "reopened", snapshot(kind)))
        obj = bpy.data.objects[name]
        if cycle % 2 == 1:  # Blender's Apply after reopening a file where an Alt D copy was deleted
            alt_d = duplicate(obj, linked=True)
            update()
            delete(alt_d)
            update()
            save_and_reopen(path)
            obj = bpy.data.objects[name]
            result, output = blender_apply(obj)
            notes.append((cycle, f"after Alt D, deleting it, save and reopen, Blender's Apply: {result}",
                          result == {'FINISHED'} and obj.data.users == 1))
            if not has_entry(kind, obj):
                add_entry(kind, obj)
            update()
    # Every entry removed: nothing of the add-on stays.
    for obj in [obj for obj in bpy.data.objects if obj.users_scene and has_entry(kind, obj)]:
        remove_entry(kind, obj)
        update()
    snapshots.append(("end", "saved", snapshot(kind)))
    save_and_reopen(path)
    snapshots.append(("end", "reopened", snapshot(kind)))
    return snapshots, notes


def compare(theirs, ours, label):
    for (cycle, when, blender), (_, _, loop) in zip(theirs, ours):
        live = blender["live"]
        what = f"{label}, cycle {cycle}, {when}"
        print(f"  {what}: objects {loop['counts']['objects']} (Subdivision Surface {blender['counts']['objects']}), "
              f"meshes {loop['counts']['meshes']} ({blender['counts']['meshes']}), node groups "
              f"{loop['counts']['node_groups']} ({blender['counts']['node_groups']}), live entries {loop['live']} "
              f"({live}), orphans {loop['orphans']} ({blender['orphans']})")
        check(loop["live"] == live, f"{what}: as many live entries ({live})")
        check(loop["visible_objects"] == blender["visible_objects"] and loop["visible_meshes"] == blender[
            "visible_meshes"], f"{what}: the objects and meshes the artist sees are as many as with Subdivision "
                               f"Surface ({blender['visible_objects']}, {blender['visible_meshes']})")
        extra = {name: loop["counts"][name] - blender["counts"][name] for name in COLLECTIONS}
        allowed = {"objects", "meshes", "node_groups"}
        check(all(0 <= extra[name] <= live for name in allowed)
              and all(extra[name] == 0 for name in COLLECTIONS if name not in allowed),
              f"{what}: at most one helper object, result mesh and node group more per live entry, nothing else "
              f"({ {name: n for name, n in extra.items() if n} })")
        check(loop["orphans"] == blender["orphans"], f"{what}: the same data without users ({blender['orphans']})")
        if when == "reopened":
            check(not loop["orphans"], f"{what}: nothing without users after reopening")
    check(ours[-1][2]["counts"] == theirs[-1][2]["counts"],
          f"{label}, every entry removed, saved and reopened: the file holds exactly what Subdivision Surface's does")


def original_deleted(base):
    """Alt D, then the original deleted: the copy keeps showing the subdivision through one helper, and only it uses
    the mesh."""
    for kind in ('SUBSURF', 'LOOP', 'ADAPTIVE'):
        bpy.ops.wm.open_mainfile(filepath=base)
        update()
        obj = support.object_from_bmesh("Original", support.cube("Original"))
        add_entry(kind, obj)
        update()
        copy = duplicate(obj, linked=True)
        update()
        delete(obj)
        update()
        faces = viewport_faces(copy)
        not_in_scenes = [other.name for other in bpy.data.objects if not other.users_scene]
        check(copy.data.users == 1 and faces > len(copy.data.polygons)
              and len(not_in_scenes) == (0 if kind == 'SUBSURF' else 1),
              f"{kind}: Alt D, the original deleted: the copy alone uses the mesh and shows {faces} faces "
              f"(objects in no scene: {not_in_scenes})")


def copied_and_pasted(base):
    """Ctrl C of an object with an entry, Ctrl V into another file (view3d.copybuffer and pastebuffer): the scene
    holds the same objects as with Subdivision Surface (the copy buffer's helper in no collection), and the pasted
    object shows its subdivision."""
    scenes = {}
    for kind in ('SUBSURF', 'LOOP'):
        bpy.ops.wm.open_mainfile(filepath=base)
        obj = support.object_from_bmesh("Copied", support.cube("Copied"))
        add_entry(kind, obj)
        update()
        select(obj)
        assert bpy.ops.view3d.copybuffer() == {'FINISHED'}
        bpy.ops.wm.open_mainfile(filepath=base)
        assert bpy.ops.view3d.pastebuffer() == {'FINISHED'}
        update()
        pasted = bpy.data.objects["Copied"]
        scenes[kind] = sorted(other.name for other in bpy.context.scene.objects)
        if kind == 'LOOP':
            faces = viewport_faces(pasted)
            check(faces == 4 * len(pasted.data.polygons), f"the pasted object shows its level 1 ({faces} faces)")
    check(scenes['LOOP'] == scenes['SUBSURF'],
          f"pasted, the scene holds what it holds with Subdivision Surface ({scenes['LOOP']}, {scenes['SUBSURF']})")


def legacy_file(base, folder):
    """A file of the add-on's earlier versions: each helper held its owner as an ID pointer, so a deleted Alt D copy
    stayed in the file with the original's mesh shared."""
    bpy.ops.wm.open_mainfile(filepath=base)
    obj = support.object_from_bmesh("Legacy", support.cube("Legacy"))
    add_entry('LOOP', obj)
    update()
    copy = duplicate(obj, linked=True)
    update()
    owner_tag = addon.blender.stack.OWNER_TAG
    for helper in [other for other in bpy.data.objects if owner_tag in other]:
        helper[owner_tag] = bpy.data.objects[helper[owner_tag]]  # as the earlier versions stored it
    copy_name = copy.name
    delete(copy)  # without updates in between: the file keeps what those versions kept
    check(bpy.data.objects.get(copy_name) is not None and obj.data.users == 2,
          "earlier versions' owner pointers keep a deleted linked copy (and its share of the mesh)")
    path = os.path.join(folder, "legacy.blend")
    addon.unregister()  # saved by a Blender without this version's handlers
    bpy.ops.wm.save_as_mainfile(filepath=path)
    addon.register()
    bpy.ops.wm.open_mainfile(filepath=path)
    update()
    obj = bpy.data.objects["Legacy"]
    check(bpy.data.objects.get(copy_name) is None and obj.data.users == 1,
          "opened with this version, the deleted copy is gone and the mesh has one user again")
    check(all(isinstance(other[owner_tag], str) for other in bpy.data.objects if owner_tag in other),
          "the helpers name their owners")
    result, _ = blender_apply(obj)
    check(result == {'FINISHED'}, "Blender's Apply works")
    save_and_reopen(path)
    orphans = [block.name for name in COLLECTIONS for block in getattr(bpy.data, name) if block.users == 0]
    check(not orphans, f"nothing without users after saving and reopening ({orphans})")


def duplicated_entry_converted(base):
    """The entry's menu ▸ Duplicate (the copy kept, or removed again), then Object ▸ Convert ▸ Mesh: the subdivision
    becomes the mesh, the helpers go, and Blender prints no error (3.4.1 counts a user of the helper for the copy
    that nothing gives back)."""
    for removed in (False, True):
        bpy.ops.wm.open_mainfile(filepath=base)
        bpy.ops.mesh.primitive_monkey_add()
        obj = bpy.context.object
        add_entry('LOOP', obj)
        update()
        faces = viewport_faces(obj)
        with bpy.context.temp_override(object=obj, active_object=obj):
            bpy.ops.object.modifier_copy(modifier=obj.modifiers[-1].name)
            if removed:
                bpy.ops.object.modifier_remove(modifier=obj.modifiers[-1].name)
        update()
        select(obj)

        def convert():
            with bpy.context.temp_override(object=obj, active_object=obj, selected_objects=[obj],
                                           selected_editable_objects=[obj]):
                result = bpy.ops.object.convert(target='MESH')
            update()
            return result

        result, printed = support.capture_output(convert, sys.stderr)
        what = "removed again" if removed else "kept"
        helpers = [other.name for other in bpy.data.objects if addon.blender.stack.is_helper(other)]
        check(result == {'FINISHED'} and len(obj.data.polygons) == faces and not obj.modifiers and not helpers,
              f"a duplicated entry ({what}), then Convert ▸ Mesh: the mesh is the subdivision, no helper stays")
        check("ERROR" not in printed, f"a duplicated entry ({what}), then Convert ▸ Mesh: no error on the console "
                                      f"({printed.strip()!r})")


with tempfile.TemporaryDirectory() as folder:
    base = base_file(folder)
    theirs, their_notes = run('SUBSURF', base, folder)
    for cycle, what, passed in their_notes:
        check(passed, f"Subdivision Surface, cycle {cycle}: {what}")
    for kind, label in (('LOOP', "Loop Subdivision"), ('ADAPTIVE', "Adaptive Subdivision")):
        ours, our_notes = run(kind, base, folder)
        for cycle, what, passed in our_notes:
            check(passed, f"{label}, cycle {cycle}: {what}")
        compare(theirs, ours, label)
    original_deleted(base)
    copied_and_pasted(base)
    legacy_file(base, folder)
    duplicated_entry_converted(base)
    bpy.ops.wm.open_mainfile(filepath=base)

addon.unregister()
check.finish()
