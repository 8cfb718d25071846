"""Per-object settings of the Loop Subdivision entry (Object.loop_subdivision)."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import geometry, preview

RULES_ITEMS = (
    ('HOPPE94', "Seed (Hoppe 94)",
     "Rules of Hoppe et al. 94 as in the seed: dart, regular and irregular crease, corner and cone vertices; "
     "edges with a crease weight at or above the threshold are sharp"),
    ('OPENSUBDIV', "OpenSubdiv Compatible",
     "OpenSubdiv's Loop rules, as Blender's Subdivision Surface: crease weights are semi-sharp creases"),
)
BOUNDARY_ITEMS = (
    ('SMOOTH', "Smooth", "Smooth boundaries, like Boundary Smooth: All of the Subdivision Surface modifier"),
    ('KEEP_CORNERS', "Keep Corners", "Boundary vertices with a single face stay sharp corners"),
)


def _changed(self, context):
    preview.settings_changed(self.id_data)


class LoopSubdivisionSettings(bpy.types.PropertyGroup):
    enabled: BoolProperty(
        name="Loop Subdivision", default=False,
        description="The object has a Loop Subdivision entry in its modifier stack", update=_changed)
    show_viewport: BoolProperty(
        name="Realtime", default=True, description="Display the Loop subdivision result in the viewport",
        update=_changed)
    levels: IntProperty(
        name="Levels", default=2, min=1, max=8, soft_max=5,
        description="Number of subdivisions to perform when applying")
    preview_levels: IntProperty(
        name="Levels Viewport", default=1, min=1, max=6, soft_max=3,
        description="Number of subdivisions to show in the viewport", update=_changed)
    rules: EnumProperty(
        name="Rules", items=RULES_ITEMS, default='HOPPE94',
        description="Which subdivision rules turn crease weights into creases", update=_changed)
    crease_threshold: FloatProperty(
        name="Crease Threshold", default=0.5, min=0.0, max=1.0, subtype='FACTOR',
        description="Edges and vertices with a crease weight at or above this value are creases and corners "
                    "(Seed rules)", update=_changed)
    boundary: EnumProperty(
        name="Boundary", items=BOUNDARY_ITEMS, default='SMOOTH',
        description="How boundary vertices with a single face are treated", update=_changed)
    use_creases: BoolProperty(
        name="Use Creases", default=True, description="Use mesh crease information to sharpen edges or corners",
        update=_changed)
    cone_group: StringProperty(
        name="Cone Group", default="",
        description="Vertex group whose vertices are cones: their surface comes to a point (Seed rules)",
        update=_changed)
    # The cage is shown as a wireframe while the preview draws the result; this remembers how it was shown.
    cage_display_type: StringProperty(default="")

    def options(self, **overrides):
        values = {name: getattr(self, name)
                  for name in ("levels", "rules", "crease_threshold", "boundary", "use_creases", "cone_group")}
        values.update(overrides)
        return geometry.Options(**values)


def register():
    bpy.utils.register_class(LoopSubdivisionSettings)
    bpy.types.Object.loop_subdivision = bpy.props.PointerProperty(type=LoopSubdivisionSettings)


def unregister():
    del bpy.types.Object.loop_subdivision
    bpy.utils.unregister_class(LoopSubdivisionSettings)
