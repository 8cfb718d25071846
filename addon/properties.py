"""Settings of an object's Loop Subdivision entry (Object.loop_subdivision), drawn in the entry's panel."""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, StringProperty

from . import geometry, live

RULES_ITEMS = (
    ('HOPPE94', "Hoppe 94 (sharp creases, cones)",
     "The rules of Hoppe et al. 94, as in the GDC'99 talk: creases stay sharp, with dart, crease, corner and cone "
     "vertices. Edges whose crease weight reaches the threshold are creases"),
    ('OPENSUBDIV', "OpenSubdiv (as Subdivision Surface)",
     "OpenSubdiv's Loop rules, which Blender's Subdivision Surface uses: crease weights give semi-sharp creases"),
)
# Subdivision Surface's own identifiers, names and descriptions (geometry.UV_SMOOTH maps them to the core's modes).
UV_SMOOTH_ITEMS = (
    ('NONE', "None", "UVs are not smoothed, boundaries are kept sharp"),
    ('PRESERVE_CORNERS', "Keep Corners", "UVs are smoothed, corners on discontinuous boundary are kept sharp"),
    ('PRESERVE_CORNERS_AND_JUNCTIONS', "Keep Corners, Junctions",
     "UVs are smoothed, corners on discontinuous boundary and junctions of 3 or more regions are kept sharp"),
    ('PRESERVE_CORNERS_JUNCTIONS_AND_CONCAVE', "Keep Corners, Junctions, Concave",
     "UVs are smoothed, corners on discontinuous boundary, junctions of 3 or more regions and darts and concave "
     "corners are kept sharp"),
    ('PRESERVE_BOUNDARIES', "Keep Boundaries", "UVs are smoothed, boundaries are kept sharp"),
    ('SMOOTH_ALL', "All", "UVs and boundaries are smoothed"),
)
LIMIT_SURFACE_DESCRIPTION = ("Place vertices at the surface that would be produced with infinite levels of "
                             "subdivision (smoothest possible shape)")
UV_SMOOTH_DESCRIPTION = "Controls how smoothing is applied to UVs"
STORE_RESULT_DESCRIPTION = ("Save the result at Render levels in the file, for machines without the add-on (render "
                            "farms). Off, the file holds the cage and the settings, as with Subdivision Surface, and "
                            "the result is made again when the file is opened")
BOUNDARY_ITEMS = (
    ('SMOOTH', "All", "Smooth boundaries, as Boundary Smooth: All of Subdivision Surface"),
    ('KEEP_CORNERS', "Keep Corners", "Boundary vertices with a single face stay sharp corners"),
)


def _changed(self, context):
    live.settings_changed(self.id_data)


class LoopSubdivisionSettings(bpy.types.PropertyGroup):
    levels: IntProperty(
        name="Levels Viewport", default=1, min=0, max=6, soft_max=3, update=_changed,
        description="Number of subdivisions to perform in the 3D viewport, and when applying")
    render_levels: IntProperty(
        name="Render", default=2, min=0, max=8, soft_max=4,
        description="Number of subdivisions to perform when rendering")
    rules: EnumProperty(
        name="Rules", items=RULES_ITEMS, default='HOPPE94', update=_changed,
        description="How crease weights shape the surface")
    crease_threshold: FloatProperty(
        name="Crease Threshold", default=0.5, min=0.0, max=1.0, subtype='FACTOR', update=_changed,
        description="Edges and vertices with a crease weight at or above this value are creases and corners")
    boundary: EnumProperty(
        name="Boundary Smooth", items=BOUNDARY_ITEMS, default='SMOOTH', update=_changed,
        description="Controls how open boundaries are smoothed")
    use_creases: BoolProperty(
        name="Use Creases", default=True, update=_changed,
        description="Use mesh crease information to sharpen edges or corners")
    cone_group: StringProperty(
        name="Cone Group", default="", update=_changed,
        description="Vertex group whose vertices become cones: the surface comes to a point there")
    use_limit_surface: BoolProperty(
        name="Use Limit Surface", default=True, update=_changed, description=LIMIT_SURFACE_DESCRIPTION)
    uv_smooth: EnumProperty(
        name="UV Smooth", items=UV_SMOOTH_ITEMS, default='PRESERVE_BOUNDARIES', update=_changed,
        description=UV_SMOOTH_DESCRIPTION)

    store_result: BoolProperty(
        name="Store Result", default=False,
        description=STORE_RESULT_DESCRIPTION)

    def options(self, **overrides):
        values = {name: getattr(self, name)
                  for name in ("levels", "rules", "crease_threshold", "boundary", "use_creases", "cone_group",
                               "use_limit_surface", "uv_smooth")}
        values.update(overrides)
        return geometry.Options(**values)


def register():
    bpy.utils.register_class(LoopSubdivisionSettings)
    bpy.types.Object.loop_subdivision = bpy.props.PointerProperty(type=LoopSubdivisionSettings)


def unregister():
    del bpy.types.Object.loop_subdivision
    bpy.utils.unregister_class(LoopSubdivisionSettings)
