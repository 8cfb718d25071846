"""Settings of an object's Loop Subdivision entry (Object.loop_subdivision), drawn in the entry's panel."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from ..live import engine
from ..model import settings

_KINDS = {bool: BoolProperty, int: IntProperty, float: FloatProperty, str: StringProperty}


def bpy_property(setting, **changes):
    """The bpy property of a setting of settings.SETTINGS; changes override its arguments (update, options, a label
    or limits of its own)."""
    arguments = dict(name=setting.label, default=setting.default, description=setting.description, **setting.limits)
    arguments.update(changes)
    if setting.choices:
        items = tuple((choice.identifier, choice.name, choice.description) for choice in setting.choices)
        return EnumProperty(items=items, **arguments)
    return _KINDS[type(setting.default)](**arguments)


def _changed(self, context):
    engine.settings_changed(self.id_data)


class LoopSubdivisionSettings(bpy.types.PropertyGroup):
    __annotations__ = {setting.name: bpy_property(setting, **({"update": _changed} if setting.live else {}))
                       for setting in settings.SETTINGS}

    def options(self, render=False, **overrides):
        """The settings of one subdivision: the viewport's, or with render the Render levels and dicing rate; overrides
        (the operators' arguments) replace any."""
        values = {name: getattr(self, name) for name in settings.SUBDIVISION}
        if render:
            values.update(levels=self.render_levels, dicing_rate=self.render_dicing_rate)
        values.update(overrides)
        return settings.Options(**values)


def register():
    bpy.utils.register_class(LoopSubdivisionSettings)
    bpy.types.Object.loop_subdivision = bpy.props.PointerProperty(type=LoopSubdivisionSettings)


def unregister():
    del bpy.types.Object.loop_subdivision
    bpy.utils.unregister_class(LoopSubdivisionSettings)
