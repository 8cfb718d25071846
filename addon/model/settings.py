"""The settings of a Loop Subdivision entry, in one table. The panel's properties (properties.py), the operators'
arguments (operators.py) and the options of one subdivision (Options, which the core's keyword arguments come from)
are all made from it, so that a name, a default, a limit or a description is written once.

No bpy here: tests load this file with plain Python.
"""
import os
from dataclasses import dataclass, field, make_dataclass


@dataclass(frozen=True)
class Choice:
    """One item of a setting with a list of choices: Blender's identifier, name and description, and the name the
    core gives it (None where the core does not take it)."""
    identifier: str
    name: str
    description: str
    core: str = None


@dataclass(frozen=True)
class Setting:
    name: str
    label: str
    default: object
    description: str
    choices: tuple = ()
    limits: dict = field(default_factory=dict)  # min, max, soft_min, soft_max, subtype: as bpy.props takes them
    live: bool = True  # a change updates the viewport's result (Render levels and Store Result do not)


SETTINGS = (
    Setting("levels", "Levels Viewport", 1,
            "Number of subdivisions to perform in the 3D viewport, and when applying",
            limits=dict(min=0, max=6, soft_max=3)),
    Setting("render_levels", "Render", 2, "Number of subdivisions to perform when rendering",
            limits=dict(min=0, max=8, soft_max=4), live=False),
    Setting("rules", "Rules", 'HOPPE94', "How crease weights shape the surface", choices=(
        Choice('HOPPE94', "Hoppe 94 (sharp creases, cones)",
               "The rules of Hoppe et al. 94, as in the GDC'99 talk: creases stay sharp, with dart, crease, corner "
               "and cone vertices. Edges whose crease weight reaches the threshold are creases", "hoppe94"),
        Choice('OPENSUBDIV', "OpenSubdiv (as Subdivision Surface)",
               "OpenSubdiv's Loop rules, which Blender's Subdivision Surface uses: crease weights give semi-sharp "
               "creases", "opensubdiv"),
    )),
    Setting("crease_threshold", "Crease Threshold", 0.5,
            "Edges and vertices with a crease weight at or above this value are creases and corners",
            limits=dict(min=0.0, max=1.0, subtype='FACTOR')),
    Setting("boundary", "Boundary Smooth", 'SMOOTH', "Controls how open boundaries are smoothed", choices=(
        Choice('SMOOTH', "All", "Smooth boundaries, as Boundary Smooth: All of Subdivision Surface", "edges"),
        Choice('KEEP_CORNERS', "Keep Corners", "Boundary vertices with a single face stay sharp corners",
               "edges-and-corners"),
    )),
    Setting("use_creases", "Use Creases", True, "Use mesh crease information to sharpen edges or corners"),
    Setting("cone_group", "Cone Group", "",
            "Vertex group whose vertices become cones: the surface comes to a point there"),
    Setting("use_limit_surface", "Use Limit Surface", True,
            "Place vertices at the surface that would be produced with infinite levels of subdivision (smoothest "
            "possible shape)"),
    # Subdivision Surface's own identifiers, names and descriptions, with the core's face-varying interpolation for
    # each as Blender maps it (BKE_subdiv_fvar_interpolation_from_uv_smooth): None keeps UVs linear everywhere, All
    # smooths them everywhere.
    Setting("uv_smooth", "UV Smooth", 'PRESERVE_BOUNDARIES', "Controls how smoothing is applied to UVs", choices=(
        Choice('NONE', "None", "UVs are not smoothed, boundaries are kept sharp", "all"),
        Choice('PRESERVE_CORNERS', "Keep Corners", "UVs are smoothed, corners on discontinuous boundary are kept "
               "sharp", "corners"),
        Choice('PRESERVE_CORNERS_AND_JUNCTIONS', "Keep Corners, Junctions",
               "UVs are smoothed, corners on discontinuous boundary and junctions of 3 or more regions are kept "
               "sharp", "corners-plus1"),
        Choice('PRESERVE_CORNERS_JUNCTIONS_AND_CONCAVE', "Keep Corners, Junctions, Concave",
               "UVs are smoothed, corners on discontinuous boundary, junctions of 3 or more regions and darts and "
               "concave corners are kept sharp", "corners-plus2"),
        Choice('PRESERVE_BOUNDARIES', "Keep Boundaries", "UVs are smoothed, boundaries are kept sharp",
               "boundaries"),
        Choice('SMOOTH_ALL', "All", "UVs and boundaries are smoothed", "none"),
    )),
    # Cycles' adaptive subdivision's names and defaults (its Dicing Rate Render and Viewport, in pixels).
    Setting("use_adaptive", "Adaptive Subdivision", False,
            "Cut each face as finely as the camera sees it, on the limit surface (the scene camera when rendering "
            "and applying, the 3D Viewport's view in the viewport), instead of by levels"),
    Setting("dicing_rate", "Dicing Rate Viewport", 8.0, "Size of a micropolygon in pixels in the 3D viewport",
            limits=dict(min=0.1, max=1000.0, soft_min=0.5, subtype='PIXEL')),
    Setting("render_dicing_rate", "Render", 1.0, "Size of a micropolygon in pixels when rendering and applying",
            limits=dict(min=0.1, max=1000.0, soft_min=0.5, subtype='PIXEL'), live=False),
    Setting("dicing_measure", "Dicing Measure", 'LENGTH', "What the dicing rate holds each segment to", choices=(
        Choice('LENGTH', "Length", "Each segment at most the dicing rate long on screen, as Cycles dices", "length"),
        Choice('DEVIATION', "Deviation", "Each segment strays at most the dicing rate from the surface on screen: "
               "flat stretches stay coarse however long they are", "deviation"),
    )),
    Setting("max_rate", "Max Segments", 64, "Largest number of segments an edge of the cage is cut into",
            limits=dict(min=1, max=4096, soft_max=256)),
    Setting("store_result", "Store Result", False,
            "Save the result at Render levels in the file, for machines without the add-on (render farms): the "
            "result of the frame the file is saved at, which such a machine renders on every frame. Off, the file "
            "holds the cage and the settings, as with Subdivision Surface, and the result is made again when the "
            "file is opened", live=False),
)
BY_NAME = {setting.name: setting for setting in SETTINGS}

# What one subdivision reads: the settings but the Render levels and dicing rate (a render passes them as levels and
# dicing_rate) and Store Result.
SUBDIVISION = tuple(setting.name for setting in SETTINGS
                    if setting.name not in ("render_levels", "render_dicing_rate", "store_result"))


def core_name(name, identifier):
    """The core's name of a choice of the setting called name ("boundaries" for uv_smooth 'PRESERVE_BOUNDARIES')."""
    return next(choice.core for choice in BY_NAME[name].choices if choice.identifier == identifier)


# The core's threads: every core, as Blender's own modifiers use them (any count gives the same bits; the core takes
# at most 256).
THREADS = max(1, min(os.cpu_count() or 1, 256))


def _plan_keywords(self):
    """Keyword arguments of _loopsub.Plan for these options (tags, cones and UV layers come from the mesh)."""
    return {
        "threads": THREADS,
        "rules": core_name("rules", self.rules),
        "boundary": core_name("boundary", self.boundary),
        "crease_threshold": float(self.crease_threshold) if self.rules == 'HOPPE94' else 0.0,
        "limit_surface": bool(self.use_limit_surface),
        "uv_interpolation": core_name("uv_smooth", self.uv_smooth),
    }


def _tessellation_keywords(self):
    """Keyword arguments of _loopsub.Tessellation for these options (tags, cones, UV layers and rates come from the
    mesh)."""
    keywords = _plan_keywords(self)
    del keywords["limit_surface"]
    return keywords


def _rate_keywords(self):
    """Keyword arguments of _loopsub.screen_space_rates for these options (Adaptive Subdivision)."""
    return {"pixels": float(self.dicing_rate), "max_rate": int(self.max_rate),
            "measure": core_name("dicing_measure", self.dicing_measure)}


# Options(levels=2, rules='OPENSUBDIV', ...): one subdivision's settings, the defaults the table's.
Options = make_dataclass(
    "Options", [(name, type(BY_NAME[name].default), field(default=BY_NAME[name].default)) for name in SUBDIVISION],
    namespace={"plan_keywords": _plan_keywords, "tessellation_keywords": _tessellation_keywords,
               "rate_keywords": _rate_keywords,
               "__doc__": "Settings of one subdivision (the panel's, overridden by the operator's arguments)."})
