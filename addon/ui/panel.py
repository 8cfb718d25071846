"""The Loop Subdivision modifier's settings, drawn inside its panel in Properties ▸ Modifiers, laid out like
Blender's Subdivision Surface; and the Add Loop Subdivision button under Add Modifier."""
import re
import textwrap

import bpy

from ..blender import interface, stack
from ..live import engine
from ..model import memory

# Estimated width of a character of the interface font, and what a label's icon and the panel's margins take, in
# pixels at a resolution scale of 1: enough to wrap notes at about the panel's width (as Blender's own panels do
# with a helper that measures the text).
_CHAR_WIDTH = 6.0
_LABEL_MARGIN = 90.0
_MIN_COLUMNS = 20


def note_columns(context):
    """How many characters of a note fit on one line of the panel, estimated from the region's width; None where
    there is no region (nothing is drawn)."""
    region = getattr(context, "region", None)
    if region is None or region.width <= 1:
        return None
    scale = context.preferences.system.ui_scale if context.preferences is not None else 0.0
    scale = scale if scale > 0 else 1.0  # 0 in background mode
    return max(_MIN_COLUMNS, int((region.width / scale - _LABEL_MARGIN) / _CHAR_WIDTH))


# An amount and its unit stay on one line ("21 GB", "8 px"): the space between them does not break.
_UNIT = re.compile(r"(\d) (MB|GB|px)\b")


def note_lines(text, columns):
    """The lines a note is drawn in: split at word boundaries to at most columns characters (long words and amounts
    with their units stay whole), the whole note on one line when columns is None."""
    if columns is None:
        return [text]
    kept = _UNIT.sub("\\1\u00a0\\2", text)
    lines = textwrap.wrap(kept, width=columns, break_long_words=False, break_on_hyphens=False) or [kept]
    return [line.replace("\u00a0", " ") for line in lines]


def _note(layout, text, icon, columns):
    """A note over as many labels as it takes at the panel's width, the icon on the first, the others indented."""
    column = layout.column(align=True)
    for index, line in enumerate(note_lines(text, columns)):
        column.label(text=line, icon=icon if index == 0 else 'BLANK1')


# What a saved file grows by per triangle of a stored result (a UV map, limit normals; measured, docs/benchmark.md),
# uncompressed and compressed (Preferences ▸ Save & Load ▸ Compress File: on by default from 5.0).
STORED_BYTES_PER_TRIANGLE = 100
STORED_BYTES_PER_TRIANGLE_COMPRESSED = 30


def stored_bytes(obj, modifier):
    """About how much store_result adds to the file: the result's triangles at Render levels (or dicing rate), from
    the viewport's result where there is one (it holds what the modifiers above make), else from the object's own
    faces; the file compressed as the preferences say new files are."""
    settings = obj.loop_subdivision
    helper = stack.helper_of(obj, modifier, create=False)
    cache = engine.cache_of(obj)
    shown = helper is not None and cache is not None and not cache.error
    if settings.use_adaptive:
        # Segments per edge go as one over the dicing rate, triangles as its square (up to Max Segments).
        mesh = helper.data if shown else obj.data
        triangles = len(mesh.polygons) * (settings.dicing_rate / settings.render_dicing_rate) ** 2
    elif shown and settings.levels > 0:
        triangles = len(helper.data.polygons) * 4 ** (settings.render_levels - settings.levels)
    else:
        mesh = obj.data
        triangles = (len(mesh.loops) - 2 * len(mesh.polygons)) * 4 ** settings.render_levels
    compressed = bpy.context.preferences.filepaths.use_file_compression
    return triangles * (STORED_BYTES_PER_TRIANGLE_COMPRESSED if compressed else STORED_BYTES_PER_TRIANGLE)


def _draw_settings(layout, obj, modifier, columns=None):
    """The entry's settings, laid out like Subdivision Surface's panel; notes wrapped at columns characters."""
    if stack.entry(obj) != modifier:
        _note(layout, "Only the first Loop Subdivision modifier is used", 'ERROR', columns)
        return
    settings = obj.loop_subdivision
    layout.use_property_split = True
    layout.use_property_decorate = False

    adaptive = settings.use_adaptive
    column = layout.column(align=True)
    column.active = not adaptive
    column.prop(settings, "levels", text="Levels Viewport")
    column.prop(settings, "render_levels", text="Render")
    layout.prop(settings, "use_adaptive")
    if adaptive:
        column = layout.column(align=True)
        column.prop(settings, "dicing_rate", text="Dicing Rate Viewport")
        column.prop(settings, "render_dicing_rate", text="Render")
        layout.prop(settings, "dicing_measure")
        layout.prop(settings, "max_rate")
    layout.prop(settings, "rules")
    threshold = layout.row()
    threshold.active = settings.use_creases and settings.rules == 'HOPPE94'
    threshold.prop(settings, "crease_threshold")
    # Adaptive Subdivision cuts the limit surface.
    limit = layout.row()
    limit.active = not adaptive
    limit.prop(settings, "use_limit_surface")
    layout.prop(settings, "uv_smooth")
    layout.prop(settings, "boundary")
    layout.prop(settings, "use_creases")
    cones = layout.row()
    cones.active = settings.rules == 'HOPPE94'
    cones.prop_search(settings, "cone_group", obj, "vertex_groups", text="Cone Group")
    layout.prop(settings, "store_result")
    if settings.store_result:
        kept = "Render dicing rate" if settings.use_adaptive else "Render level"
        _note(layout, f"The file keeps the {kept} of the frame it is saved at: about "
                      f"{memory.format_bytes(stored_bytes(obj, modifier))}",
              'INFO', columns)

    cache = engine.cache_of(obj)
    if cache is not None and cache.error:
        _note(layout, cache.error, 'ERROR', columns)
    elif cache is not None:
        for level, text in cache.messages:
            _note(layout, text.split(": ", 1)[-1], 'ERROR' if level == 'WARNING' else 'INFO', columns)
    row = layout.row(align=True)
    row.context_pointer_set("object", obj)
    row.operator("object.loop_subdivision_apply", text="Apply", icon='CHECKMARK')
    row.operator("object.loop_subdivision_refresh_tags", text="Refresh Tags", icon='FILE_REFRESH')


def _draw_entry(panel, context):
    modifier = panel.custom_data
    if modifier is not None and stack.is_entry(modifier):
        _draw_settings(panel.layout, modifier.id_data, modifier, note_columns(context))


def _draw_nothing(_panel, _context):
    """The kept sub-panel's drawing while the add-on is off."""


class DATA_PT_loop_subdivision(bpy.types.Panel):
    """A header-less part of every Geometry Nodes modifier's panel that draws only in the Loop Subdivision ones.

    Registered once per session and never unregistered (register, unregister): the modifier panels Blender has made
    keep their sub-panels' types, and a type freed under them is read on the next redraw (3.4.1 crashed when the
    add-on was turned off and on, as an update does, with the Modifier tab shown). While the add-on is off it draws
    nothing."""
    bl_label = "Loop Subdivision"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "modifier"
    bl_parent_id = interface.NODES_MODIFIER_PANEL
    bl_options = {'HIDE_HEADER'}
    draw = _draw_entry


class DATA_PT_loop_subdivision_settings(bpy.types.Panel):
    """Where a Blender version has no modifier panel to draw inside: the active object's entry, below the stack."""
    bl_label = "Loop Subdivision"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "modifier"

    @classmethod
    def poll(cls, context):
        return stack.entry(context.object) is not None

    def draw(self, context):
        _draw_settings(self.layout, context.object, stack.entry(context.object), note_columns(context))


def _add_button(self, context):
    obj = context.object
    if obj is not None and obj.type == 'MESH' and stack.entry(obj) is None:
        self.layout.operator("object.loop_subdivision_add", icon='MOD_SUBSURF')


_button_target = None
_panel = None


def _kept_panel():
    """The sub-panel type an earlier registration of this session left registered (DATA_PT_loop_subdivision), with
    the same parent; None at the session's first registration."""
    kept = getattr(bpy.types, DATA_PT_loop_subdivision.__name__, None)
    return kept if kept is not None and kept.bl_parent_id == DATA_PT_loop_subdivision.bl_parent_id else None


def register():
    global _button_target, _panel
    _panel = _kept_panel()
    if _panel is not None:
        _panel.draw = _draw_entry  # this module's drawing, also after an update or a reload
    else:
        try:
            bpy.utils.register_class(DATA_PT_loop_subdivision)
            _panel = DATA_PT_loop_subdivision
        except RuntimeError:  # no Geometry Nodes modifier panel by that name in this Blender
            bpy.utils.register_class(DATA_PT_loop_subdivision_settings)
            _panel = DATA_PT_loop_subdivision_settings
    _button_target = interface.add_modifier_button(_add_button)


def unregister():
    interface.remove_modifier_button(_button_target, _add_button)
    if _panel is DATA_PT_loop_subdivision_settings:  # a panel of its own: Blender forgets it safely
        bpy.utils.unregister_class(_panel)
    else:
        _panel.draw = _draw_nothing
