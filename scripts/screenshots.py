"""Screenshots of the add-on's panel in Blender's real interface for docs/, run by scripts/screenshots.sh (which
documents the two Blender runs). With --addon-dir: add-modifier-menu.png, modifier-panel.png,
modifier-adaptive.png, and --save FILE.blend (an entry with default settings); without it (FILE.blend opened by a
Blender without the add-on): modifier-without-addon.png.

Everything happens in bpy.app.timers stages, so that Blender's event loop evaluates, runs the add-on's handlers and
draws between them, as for an artist; each stage returns the seconds to wait before the next one.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import traceback

import bpy
import numpy as np

PROPERTIES_WIDTH = 520  # wide enough for the settings' labels and the notes on few lines
MARGIN = 8  # pixels of background kept under the last panel
BORDER = 12  # rows at the bottom of Properties drawn darker (the area's edge), never a panel


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-dir", help="the add-on as users install it; absent: a Blender without it")
    parser.add_argument("--out", required=True)
    parser.add_argument("--save", help="with --addon-dir: a file with an entry, for the run without the add-on")
    return parser.parse_known_args(argv)[0]


ARGS = arguments()
bpy.context.preferences.view.show_splash = False  # now, before Blender opens it: a popup blocks the stages
TMP = tempfile.mkdtemp()


def window():
    return bpy.context.window_manager.windows[0]


def area(kind):
    return next((a for a in window().screen.areas if a.type == kind), None)


def region(found, kind='WINDOW'):
    return next(r for r in found.regions if r.type == kind)


def override(found, **extra):
    return bpy.context.temp_override(window=window(), screen=window().screen, area=found, **extra)


def park_pointer():
    # On the edge between viewport and Properties: no button is highlighted, and area_move only runs when no region
    # is under the pointer.
    properties = area('PROPERTIES')
    window().cursor_warp(properties.x - 1, properties.y + properties.height // 2)


def arrange():
    """Properties the whole height beside the viewport, PROPERTIES_WIDTH wide, on the Modifiers tab. Runs a stage
    after park_pointer: the pointer's move must have reached the event loop."""
    properties = area('PROPERTIES')
    with override(properties):
        bpy.ops.screen.area_move(x=properties.x, y=properties.y + properties.height // 2,
                                 delta=properties.width - PROPERTIES_WIDTH)
    for kind in ('OUTLINER', 'DOPESHEET_EDITOR'):  # absent when the saved file's layout is already this one
        if area(kind) is not None:
            with override(area(kind)):
                bpy.ops.screen.area_close()
    properties = area('PROPERTIES')
    properties.spaces.active.context = 'MODIFIER'
    park_pointer()


def activate(obj):
    for other in bpy.context.view_layer.objects:
        other.select_set(False)
        other.hide_set(other is not obj and other.type == 'MESH')
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj


def content_bottom(pixels, properties):
    """The lowest window row (from the bottom, y up) that Properties' panels draw on: the rows below them are one
    colour, the region's background."""
    main = region(properties)
    block = pixels[main.y:main.y + main.height, main.x:main.x + main.width - 20, :3]  # no scrollbar
    background = block[main.height // 2, 3]  # the left margin, beside the panels
    drawn = np.nonzero(np.abs(block - background).max(axis=(1, 2)) > 0.02)[0]
    drawn = drawn[drawn > BORDER]
    return main.y + (drawn[0] if len(drawn) else 0)


def capture(name, left, right, full_height=False):
    """Takes the window and crops it to the columns [left, right) from the top of the areas down to the end of
    Properties' panels (or the areas' bottom), into OUT/name."""
    full = os.path.join(TMP, "window.png")
    with override(area('VIEW_3D')):
        bpy.ops.wm.redraw_timer(type='DRAW_WIN_SWAP', iterations=1)
        bpy.ops.screen.screenshot(filepath=full)
    image = bpy.data.images.load(full)
    pixels = np.empty(image.size[0] * image.size[1] * 4, dtype=np.float32)
    image.pixels.foreach_get(pixels)
    pixels = pixels.reshape(image.size[1], image.size[0], 4)  # rows from the bottom, as window coordinates
    bpy.data.images.remove(image)
    properties = area('PROPERTIES')
    top = properties.y + properties.height  # window y, up
    bottom = properties.y if full_height else max(properties.y, content_bottom(pixels, properties) - MARGIN)
    # Image rows count from the top.
    crop = f"{right - left}x{top - bottom}+{left}+{window().height - top}"
    out = os.path.join(ARGS.out, name)
    subprocess.run(["convert", full, "-crop", crop, "+repage", "-strip", out], check=True)
    print(f"screenshots: wrote {out} ({crop})", flush=True)


def properties_columns():
    properties = area('PROPERTIES')
    return properties.x, properties.x + properties.width


def icosphere(name):
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=1.0)  # UV-mapped (calc_uvs)
    obj = bpy.context.object
    obj.name = obj.data.name = name
    return obj


# Run with the add-on.

def setup():
    sys.path.insert(0, os.path.dirname(os.path.abspath(ARGS.addon_dir)))
    package = __import__(os.path.basename(os.path.abspath(ARGS.addon_dir)))
    package.register()
    bpy.data.objects.remove(bpy.data.objects["Cube"])
    activate(icosphere("Icosphere"))
    park_pointer()
    return 1.0


def arranged():
    arrange()
    return 1.5


def add_button():
    capture("add-modifier-menu.png", *properties_columns())
    bpy.ops.object.loop_subdivision_add(levels=2)
    return 2.0


def panel():
    capture("modifier-panel.png", *properties_columns())
    if ARGS.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(ARGS.save), copy=True)
    return 2.0


def adaptive_view():
    # Adaptive Subdivision on the sphere, the viewport close to it with the wireframe shown: the result is cut finer
    # where the sphere faces the view than at its silhouette and back.
    obj = bpy.data.objects["Icosphere"]
    activate(obj)
    obj.loop_subdivision.use_adaptive = True
    obj.loop_subdivision.dicing_rate = 20.0  # segments the picture can show
    view3d = area('VIEW_3D')
    view3d.spaces.active.overlay.show_wireframes = True
    view3d.spaces.active.overlay.wireframe_threshold = 1.0
    with override(view3d, region=region(view3d)):
        bpy.ops.view3d.view_selected()
    obj.select_set(False)  # the wireframe in its own colour, not the selection's
    return 2.0


def adaptive():
    capture("modifier-adaptive.png", area('VIEW_3D').x, properties_columns()[1], full_height=True)
    out = os.path.join(ARGS.out, "modifier-adaptive.png")  # the whole window: smaller, as the docs show it
    subprocess.run(["convert", out, "-resize", "1200x", "-colors", "128", "PNG8:" + out], check=True)
    return quit_blender()


# Run without the add-on, on the file saved by the first run.

def setup_without():
    park_pointer()
    return 1.0


def frame_without():
    arrange()
    obj = bpy.data.objects["Icosphere"]
    activate(obj)
    view3d = area('VIEW_3D')
    view3d.spaces.active.overlay.show_wireframes = True  # the cage's triangles: the result would hide them
    with override(view3d, region=region(view3d)):
        bpy.ops.view3d.view_selected()
    return 1.0


def zoom_out():
    area('VIEW_3D').spaces.active.region_3d.view_distance *= 1.3  # view_selected's smooth view has ended: room around
    return 1.0


def without_addon():
    capture("modifier-without-addon.png", area('VIEW_3D').x, properties_columns()[1], full_height=True)
    return quit_blender()


def quit_blender():
    with bpy.context.temp_override(window=window()):
        bpy.ops.wm.quit_blender()
    return None


STAGES = ([setup, arranged, add_button, panel, adaptive_view, adaptive] if ARGS.addon_dir
          else [setup_without, frame_without, zoom_out, without_addon])


def step():
    try:
        return STAGES.pop(0)()
    except Exception:
        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)


bpy.app.timers.register(step, first_interval=1.0)
