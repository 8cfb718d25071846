"""Operators: add, remove and apply the Loop Subdivision modifier, and write the crease tags."""
import bpy
from bpy.props import BoolProperty, IntProperty

from ..blender import interface, stack
from ..live import engine
from ..model import settings
from ..native import LoopSubError
from ..subdivision import adaptive, result, tags
from .properties import bpy_property


def _mesh_objects(context):
    """The selected mesh objects, the active one first (it may be active without being selected)."""
    objects = [context.object] if context.object is not None and context.object.type == 'MESH' else []
    objects += [obj for obj in context.selected_objects if obj.type == 'MESH' and obj not in objects]
    return objects


def _overrides(operator, names):
    """The settings a caller gave (SKIP_SAVE keeps a value given once from sticking to later calls)."""
    return {name: getattr(operator, name) for name in names if operator.properties.is_property_set(name)}


def _arguments(names, **changes):
    """Operator arguments named as the settings, made from their table (settings.py), SKIP_SAVE (see _overrides);
    changes: per name, what differs from the setting."""
    return {name: bpy_property(settings.BY_NAME[name], options={'SKIP_SAVE'}, **changes.get(name, {}))
            for name in names}


_LONG_APPLY_FACES = 2_000_000  # output triangles: about two seconds of applying

# The arguments of Add (every setting) and of Apply (those that shape one subdivision), which override the object's
# settings when given.
_ADD_ARGUMENTS = tuple(setting.name for setting in settings.SETTINGS)
_APPLY_OVERRIDES = ("levels", "rules", "crease_threshold", "boundary", "use_limit_surface", "uv_smooth",
                    "use_adaptive", "dicing_rate")


class OBJECT_OT_loop_subdivision_add(bpy.types.Operator):
    """Add a Loop Subdivision modifier to the end of the active object's modifier stack"""
    bl_idname = "object.loop_subdivision_add"
    bl_label = "Add Loop Subdivision"
    bl_options = {'REGISTER', 'UNDO'}
    __annotations__ = _arguments(_ADD_ARGUMENTS)

    @classmethod
    def poll(cls, context):
        obj = context.object
        if obj is None or obj.type != 'MESH':
            return False
        if stack.entry(obj) is not None:
            cls.poll_message_set("The object has a Loop Subdivision modifier already")
            return False
        return True

    def execute(self, context):
        obj = context.object
        own = obj.loop_subdivision
        for name, value in _overrides(self, _ADD_ARGUMENTS).items():
            setattr(own, name, value)
        stack.add(obj)
        engine.refresh(obj, context.evaluated_depsgraph_get())
        cache = engine.cache_of(obj)
        if cache is not None and cache.error:
            self.report({'WARNING'}, cache.error)
        return {'FINISHED'}


class OBJECT_OT_loop_subdivision_remove(bpy.types.Operator):
    """Remove the Loop Subdivision modifier from the active object"""
    bl_idname = "object.loop_subdivision_remove"
    bl_label = "Remove Loop Subdivision"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        return stack.entry(context.object) is not None

    def execute(self, context):
        context.object.modifiers.remove(stack.entry(context.object))
        return {'FINISHED'}


class OBJECT_OT_loop_subdivision_apply(bpy.types.Operator):
    """Replace the active object's mesh with its Loop subdivision, and remove its Loop Subdivision modifier.
Non-triangle faces are triangulated first. Arguments that are set override the modifier's settings"""
    bl_idname = "object.loop_subdivision_apply"
    bl_label = "Apply Loop Subdivision"
    bl_options = {'REGISTER', 'UNDO'}

    __annotations__ = _arguments(_APPLY_OVERRIDES, levels=dict(
        name="Levels", min=1, max=8, soft_max=5, description="Number of subdivisions to perform"), dicing_rate=dict(
        name="Dicing Rate", default=1.0, description="Size of a micropolygon in pixels, seen from the scene camera"))

    @classmethod
    def poll(cls, context):
        if context.mode != 'OBJECT':
            cls.poll_message_set("Switch to Object Mode to apply")
            return False
        return context.object is not None and context.object.type == 'MESH'

    def execute(self, context):
        obj = context.object
        # Adaptive Subdivision applies what a render shows: the scene camera at the Render dicing rate.
        own = obj.loop_subdivision
        options = own.options(**{"dicing_rate": own.render_dicing_rate, **_overrides(self, _APPLY_OVERRIDES)})
        modifier = stack.entry(obj)
        if modifier is not None and not stack.is_first(obj, modifier):
            # Blender's own words when a modifier that is not first is applied: it acts on the object's mesh.
            self.report({'INFO'}, "Applied modifier was not first, result may not be as expected")
        if options.levels == 0 and not options.use_adaptive:
            # Nothing to subdivide: as Blender applies Subdivision Surface at level 0.
            if modifier is not None:
                obj.modifiers.remove(modifier)
            return {'FINISHED'}
        # Adaptive Subdivision applies what the scene camera sees (levels check their memory in result.subdivide).
        view = None
        try:
            if options.use_adaptive:
                view = adaptive.scene_view(context.scene, context.evaluated_depsgraph_get())
        except LoopSubError as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        window_manager = context.window_manager
        window_manager.progress_begin(0, len(result.STAGES))  # the counter at the mouse cursor
        # The interface does not redraw while an operator runs: a long apply redraws once to say what it does
        # (a redraw costs milliseconds on a GPU, half a second with software OpenGL).
        status = None
        long_apply = not options.use_adaptive and len(obj.data.polygons) * 4 ** options.levels > _LONG_APPLY_FACES
        if not bpy.app.background and long_apply:
            status = context.workspace
            status.status_text_set(f"Loop Subdivision of {obj.name} to level {options.levels}…")
            bpy.ops.wm.redraw_timer(type='DRAW_WIN_SWAP', iterations=1)

        def progress(stage):
            window_manager.progress_update(stage)

        try:
            subdivided = result.subdivide(obj, options, progress, view)
        except LoopSubError as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        finally:
            window_manager.progress_end()
            if status is not None:
                status.status_text_set(None)
        result.replace_mesh(obj, subdivided)
        if modifier is not None:
            obj.modifiers.remove(modifier)
        for level, text in subdivided.messages:
            self.report({level}, text)
        self.report({'INFO'}, f"Applied Loop subdivision to {obj.name}")
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
                tags.tag_object(obj, obj.loop_subdivision.options())
                tagged += 1
            except LoopSubError as error:
                self.report({'ERROR'}, str(error))
        return {'FINISHED'} if tagged else {'CANCELLED'}


class OBJECT_OT_loop_subdivision_set(bpy.types.Operator):
    """Set the levels of the Loop Subdivision modifier of the selected objects that have one, and a Subdivision
    Surface level on the others (Blender's Subdivision Set)"""
    bl_idname = "object.loop_subdivision_set"
    bl_label = "Subdivision Set"
    bl_options = {'REGISTER', 'UNDO'}

    # Blender's object.subdivision_set's arguments, which the others get as they are.
    level: IntProperty(name="Level", min=-100, max=100, soft_min=-6, soft_max=6, default=1)
    relative: BoolProperty(name="Relative", default=False,
                           description="Apply the subdivision surface level as an offset relative to the current level")
    ensure_modifier: BoolProperty(name="Ensure Modifier", default=True, options={'HIDDEN'},
                                  description="Create the corresponding modifier if it does not exist")

    def execute(self, context):
        active = context.active_object
        if active is not None and active.mode in {'SCULPT', 'VERTEX_PAINT', 'WEIGHT_PAINT', 'TEXTURE_PAINT'}:
            objects = [active]  # as Blender's: paint modes act on the active object
        else:
            objects = list(context.selected_editable_objects)
        ours = [obj for obj in objects if stack.entry(obj) is not None]
        others = [obj for obj in objects if obj not in ours]
        for obj in ours:
            own = obj.loop_subdivision
            levels = own.bl_rna.properties["levels"]
            value = own.levels + self.level if self.relative else self.level
            own.levels = max(levels.hard_min, min(levels.hard_max, value))
        if others or not ours:
            arguments = interface.subdivision_set_arguments(level=self.level, relative=self.relative,
                                                         ensure_modifier=self.ensure_modifier)
            try:
                with context.temp_override(selected_editable_objects=others):
                    outcome = bpy.ops.object.subdivision_set(**arguments)
            except RuntimeError as error:  # its poll failed (nothing selected): as Blender's own says
                if not ours:
                    self.report({'WARNING'}, str(error).split("Error: ", 1)[-1].strip())
                    return {'CANCELLED'}
                outcome = {'FINISHED'}
            if not ours:
                return outcome
        return {'FINISHED'}


_SUBDIVISION_SET_KEYS = ('ZERO', 'ONE', 'TWO', 'THREE', 'FOUR', 'FIVE')
_SUBDIVISION_SET_KEYMAPS = ("Object Mode", "Mesh")  # where Blender binds them: Object Mode and Edit Mode


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
    OBJECT_OT_loop_subdivision_set,
    VIEW3D_MT_object_loop_subdivision,
)
_keymap_items = []  # (keymap, item) of Ctrl 0-5


def _add_keymap_items():
    """Ctrl 0-5 in Object and Edit Mode, as Blender binds object.subdivision_set, call loop_subdivision_set (which sets
    a Loop Subdivision modifier's levels and leaves every other object to Blender's). Add-on keymap items come before
    the default ones. No keymaps in background mode (no window manager, or a key configuration without one for
    add-ons)."""
    window_manager = bpy.context.window_manager
    keyconfig = window_manager.keyconfigs.addon if window_manager is not None else None
    if keyconfig is None:
        return
    for name in _SUBDIVISION_SET_KEYMAPS:
        keymap = keyconfig.keymaps.new(name=name, space_type='EMPTY')
        for level, key in enumerate(_SUBDIVISION_SET_KEYS):
            item = keymap.keymap_items.new(OBJECT_OT_loop_subdivision_set.bl_idname, key, 'PRESS', ctrl=True)
            item.properties.level = level
            item.properties.relative = False
            _keymap_items.append((keymap, item))


def _remove_keymap_items():
    for keymap, item in _keymap_items:
        try:
            keymap.keymap_items.remove(item)
        except (ReferenceError, RuntimeError):
            pass  # the key configuration is gone already
    _keymap_items.clear()


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.VIEW3D_MT_object.append(_object_menu)
    _add_keymap_items()


def unregister():
    _remove_keymap_items()
    bpy.types.VIEW3D_MT_object.remove(_object_menu)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
