"""Operators: add, remove and apply the Loop Subdivision entry, and refresh the crease tags."""
import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty

from . import mesh_data
from .native import LoopSubError
from .properties import BOUNDARY_ITEMS, RULES_ITEMS


def _mesh_objects(context):
    """The selected mesh objects, the active one first (it may be active without being selected)."""
    objects = [context.object] if context.object is not None and context.object.type == 'MESH' else []
    objects += [obj for obj in context.selected_objects if obj.type == 'MESH' and obj not in objects]
    return objects


class OBJECT_OT_loop_subdivision_add(bpy.types.Operator):
    """Add a Loop Subdivision entry to the active object's modifiers, with a live preview"""
    bl_idname = "object.loop_subdivision_add"
    bl_label = "Add Loop Subdivision"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.object
        return obj is not None and obj.type == 'MESH' and not obj.loop_subdivision.enabled

    def execute(self, context):
        context.object.loop_subdivision.enabled = True
        return {'FINISHED'}


class OBJECT_OT_loop_subdivision_remove(bpy.types.Operator):
    """Remove the Loop Subdivision entry from the active object"""
    bl_idname = "object.loop_subdivision_remove"
    bl_label = "Remove Loop Subdivision"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        obj = context.object
        return obj is not None and obj.type == 'MESH' and obj.loop_subdivision.enabled

    def execute(self, context):
        context.object.loop_subdivision.enabled = False
        return {'FINISHED'}


class OBJECT_OT_loop_subdivision_apply(bpy.types.Operator):
    """Replace the geometry of the selected mesh objects with their Loop subdivision.
Non-triangle faces are triangulated first. Arguments that are set override each object's panel settings"""
    bl_idname = "object.loop_subdivision_apply"
    bl_label = "Apply Loop Subdivision"
    bl_options = {'REGISTER', 'UNDO'}

    # SKIP_SAVE: a value given once must not stick to later calls, which would then ignore the panel's settings.
    levels: IntProperty(name="Levels", default=2, min=1, max=8, soft_max=5, options={'SKIP_SAVE'},
                        description="Number of subdivisions to perform")
    rules: EnumProperty(name="Rules", items=RULES_ITEMS, default='HOPPE94', options={'SKIP_SAVE'})
    crease_threshold: FloatProperty(name="Crease Threshold", default=0.5, min=0.0, max=1.0, subtype='FACTOR',
                                    options={'SKIP_SAVE'},
                                    description="Crease weights at or above this value are creases (Seed rules)")
    boundary: EnumProperty(name="Boundary", items=BOUNDARY_ITEMS, default='SMOOTH', options={'SKIP_SAVE'})

    @classmethod
    def poll(cls, context):
        if context.mode != 'OBJECT':
            cls.poll_message_set("Switch to Object Mode to apply")
            return False
        return bool(_mesh_objects(context))

    def execute(self, context):
        overrides = {name: getattr(self, name) for name in ("levels", "rules", "crease_threshold", "boundary")
                     if self.properties.is_property_set(name)}
        objects = _mesh_objects(context)
        window_manager = context.window_manager
        stages = 4  # plan, vertex data, face data, mesh (see mesh_data.subdivide)
        window_manager.progress_begin(0, stages * len(objects))
        step = 0

        def progress():
            nonlocal step
            step += 1
            window_manager.progress_update(step)

        applied = 0
        try:
            for number, obj in enumerate(objects):
                step = number * stages
                settings = obj.loop_subdivision
                try:
                    result = mesh_data.subdivide(obj, settings.options(**overrides), progress)
                except LoopSubError as error:
                    self.report({'ERROR'}, str(error))
                    continue
                mesh_data.replace_mesh(obj, result)
                # As with Blender's modifiers, applying removes the entry.
                settings.enabled = False
                applied += 1
                for level, text in result.messages:
                    self.report({level}, text)
        finally:
            window_manager.progress_end()
        if not applied:
            return {'CANCELLED'}
        self.report({'INFO'}, f"Applied Loop subdivision to {applied} object{'s' if applied > 1 else ''}")
        return {'FINISHED'}


class OBJECT_OT_loop_subdivision_refresh_tags(bpy.types.Operator):
    """Write the crease tags the rules derive from crease weights as attributes: "loop_crease" on edges and
    "loop_vertex_type" on points (see them in the Spreadsheet)"""
    bl_idname = "object.loop_subdivision_refresh_tags"
    bl_label = "Refresh Loop Subdivision Tags"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        if context.mode != 'OBJECT':
            cls.poll_message_set("Switch to Object Mode to write the tags")
            return False
        return bool(_mesh_objects(context))

    def execute(self, context):
        tagged = 0
        for obj in _mesh_objects(context):
            try:
                mesh_data.tag_object(obj, obj.loop_subdivision.options())
                tagged += 1
            except LoopSubError as error:
                self.report({'ERROR'}, str(error))
        return {'FINISHED'} if tagged else {'CANCELLED'}


class VIEW3D_MT_object_loop_subdivision(bpy.types.Menu):
    """Makes the operators reachable from the Object menu, and so from F3 search"""
    bl_label = "Loop Subdivision"
    bl_idname = "VIEW3D_MT_object_loop_subdivision"

    def draw(self, context):
        layout = self.layout
        layout.operator(OBJECT_OT_loop_subdivision_add.bl_idname, text="Add")
        layout.operator(OBJECT_OT_loop_subdivision_apply.bl_idname, text="Apply")
        layout.operator(OBJECT_OT_loop_subdivision_refresh_tags.bl_idname, text="Refresh Tags")
        layout.operator(OBJECT_OT_loop_subdivision_remove.bl_idname, text="Remove")


def _object_menu(self, context):
    self.layout.menu(VIEW3D_MT_object_loop_subdivision.bl_idname)


classes = (
    OBJECT_OT_loop_subdivision_add,
    OBJECT_OT_loop_subdivision_remove,
    OBJECT_OT_loop_subdivision_apply,
    OBJECT_OT_loop_subdivision_refresh_tags,
    VIEW3D_MT_object_loop_subdivision,
)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_object.append(_object_menu)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(_object_menu)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
