"""Retakes docs/modifier-stack.png: Suzanne with Mirror, Loop Subdivision (its panel open) and Displace, seen in the
3D Viewport and in Properties ▸ Modifiers, in Blender's default theme.

Needs a display (Blender draws its interface; a virtual one will do) and ImageMagick's `convert` for the crop:
    Xvfb :99 -screen 0 1600x1000x24 &
    DISPLAY=:99 LIBGL_ALWAYS_SOFTWARE=1 blender --factory-startup -p 0 0 900 728 \
        --python scripts/docs_screenshot.py [-- OUT.png]
The picture is the window without its top bar and status bar: 900 x 680 for that window, the height the panel needs.
Blender quits by itself once the picture is written (default: docs/modifier-stack.png; exit status 1 on a failure).
"""
import os
import subprocess
import sys
import tempfile
import traceback

import bpy
from mathutils import Euler

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else os.path.join(REPO, "docs", "modifier-stack.png")
PROPERTIES_WIDTH = 440  # wide enough for the panel's labels and values (not its long notes) to show in full

sys.path.insert(0, REPO)
import addon  # noqa: E402  (the working tree's add-on, registered as the tests do)

addon.register()
bpy.context.preferences.view.show_splash = False


def window():
    return bpy.context.window_manager.windows[0]


def areas():
    return {area.type: area for area in window().screen.areas}


def move_edge(area, x, y, delta):
    """Drags the area edge at window position (x, y) by delta pixels, as a mouse would."""
    with bpy.context.temp_override(window=window(), screen=window().screen, area=area):
        bpy.ops.screen.area_move(x=x, y=y, delta=delta)


def build_scene():
    for obj in list(bpy.data.objects):
        if obj.type == 'MESH':
            bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_monkey_add()
    obj = bpy.context.object
    bpy.ops.object.shade_smooth()
    mirror = obj.modifiers.new("Mirror", 'MIRROR')
    mirror.use_bisect_axis[0] = True  # half of Suzanne, mirrored: the same shape, no doubled faces
    bpy.ops.object.loop_subdivision_add(levels=2, render_levels=3)
    displace = obj.modifiers.new("Displace", 'DISPLACE')
    displace.strength = 0.1
    obj.modifiers.active = addon.blender.stack.entry(obj)  # the Loop Subdivision panel, outlined as the active one
    mirror.show_expanded = False
    displace.show_expanded = False


def park_pointer():
    """On the gap between the viewport and Properties: area_move runs only while no region is under the pointer."""
    properties = areas()['PROPERTIES']
    window().cursor_warp(properties.x - 1, properties.y + properties.height // 2)


def arrange():
    found = areas()
    view3d, properties = found['VIEW_3D'], found['PROPERTIES']
    properties.spaces.active.context = 'MODIFIER'
    # The vertical edge between the viewport and the editors on the right.
    move_edge(properties, properties.x, properties.y + properties.height // 2, properties.width - PROPERTIES_WIDTH)
    # Properties takes the Outliner's place (the whole height beside the viewport), the viewport the Timeline's.
    for closing in (found['OUTLINER'], found['DOPESHEET_EDITOR']):
        with bpy.context.temp_override(window=window(), screen=window().screen, area=closing):
            bpy.ops.screen.area_close()
    park_pointer()
    space = view3d.spaces.active
    space.region_3d.view_rotation = Euler((1.2, 0.0, 0.65)).to_quaternion()
    space.region_3d.view_location = (0.15, 0.0, 0.0)
    space.region_3d.view_distance = 3.7
    return 2.0


def shoot():
    found = areas()
    view3d, properties = found['VIEW_3D'], found['PROPERTIES']
    full = os.path.join(tempfile.mkdtemp(), "window.png")
    with bpy.context.temp_override(window=window(), screen=window().screen, area=view3d):
        bpy.ops.screen.screenshot(filepath=full)  # the whole window
    # The two areas, without the top bar and the status bar. Window coordinates start at the bottom, the picture's
    # at the top.
    width = properties.x + properties.width - view3d.x
    top = window().height - (properties.y + properties.height)
    crop = f"{width}x{properties.height}+{view3d.x}+{top}"
    subprocess.run(["convert", full, "-crop", crop, "+repage", OUT], check=True)
    print(f"wrote {OUT} ({crop})")
    with bpy.context.temp_override(window=window()):
        bpy.ops.wm.quit_blender()


def prepare():
    build_scene()
    park_pointer()
    return 1.0  # seconds until the next stage, for Blender to redraw


STAGES = [prepare, arrange, shoot]


def step():
    try:
        return STAGES.pop(0)()
    except Exception:
        traceback.print_exc()
        os._exit(1)


bpy.app.timers.register(step, first_interval=1.0)
