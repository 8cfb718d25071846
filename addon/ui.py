"""The Loop Subdivision panel in Properties ▸ Modifiers, laid out like Blender's Subdivision Surface modifier."""
import bpy

from . import preview


class DATA_PT_loop_subdivision(bpy.types.Panel):
    bl_label = "Loop Subdivision"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "modifier"
    bl_options = {'HIDE_HEADER'}

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == 'MESH'

    def draw(self, context):
        layout = self.layout
        obj = context.object
        settings = obj.loop_subdivision
        if not settings.enabled:
            layout.operator("object.loop_subdivision_add", icon='MOD_SUBSURF')
            return

        box = layout.box()
        header = box.row(align=True)
        header.label(text="Loop Subdivision", icon='MOD_SUBSURF')
        header.prop(settings, "show_viewport", text="", icon='RESTRICT_VIEW_OFF' if settings.show_viewport
                    else 'RESTRICT_VIEW_ON', emboss=False)
        header.operator("object.loop_subdivision_remove", text="", icon='X', emboss=False)

        column = box.column()
        column.use_property_split = True
        column.use_property_decorate = False
        column.prop(settings, "preview_levels", text="Levels Viewport")
        column.prop(settings, "levels", text="Apply")
        column.separator()
        column.prop(settings, "rules")
        threshold = column.row()
        threshold.active = settings.use_creases and settings.rules == 'HOPPE94'
        threshold.prop(settings, "crease_threshold")
        column.prop(settings, "boundary")
        column.prop(settings, "use_creases")
        cones = column.row()
        cones.active = settings.rules == 'HOPPE94'
        cones.prop_search(settings, "cone_group", obj, "vertex_groups", text="Cone Group")

        item = preview.entry(obj)
        if item is not None and item.error:
            box.label(text=item.error, icon='ERROR')

        row = box.row(align=True)
        row.operator("object.loop_subdivision_apply", text="Apply", icon='CHECKMARK')
        row.operator("object.loop_subdivision_refresh_tags", text="Refresh Tags", icon='FILE_REFRESH')


def register():
    bpy.utils.register_class(DATA_PT_loop_subdivision)


def unregister():
    bpy.utils.unregister_class(DATA_PT_loop_subdivision)
