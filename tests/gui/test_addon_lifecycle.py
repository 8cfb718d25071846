"""The add-on turned off and on, updated from a newer zip and reloaded by Reload Scripts, each with the Modifier tab
shown (Debian's Blender 3.4.1 under Xvfb): Blender keeps running and the entry is live again within a redraw or two.

Run as ctest's gui.test_addon_lifecycle: `xvfb-run blender --factory-startup --python THIS -- --addon-dir DIR
--package-dir DIR`. The add-on is installed from its zip as an artist installs it (Preferences ▸ Add-ons ▸ Install,
into a scripts folder under build/ named by the session's preferences, which --factory-startup never saves). Each
step runs from a timer, as an artist's actions arrive between redraws; screenshots of the window go to
build/gui-shots/. The process ends with the checks' exit code; a crash ends it with a signal.
"""
import argparse
import glob
import os
import shutil
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
import blender_test_support as support  # noqa: E402

MODULE = "loop_subdivision"
check = support.Check("test_addon_lifecycle")
bpy.context.preferences.view.show_splash = False  # now, before Blender opens it over the window
_arguments = argparse.ArgumentParser()
_arguments.add_argument("--addon-dir", required=True)
_arguments.add_argument("--package-dir", required=True)
args, _ = _arguments.parse_known_args(sys.argv[sys.argv.index("--") + 1:])
BUILD = os.path.dirname(os.path.dirname(os.path.abspath(args.addon_dir)))
SCRIPTS = os.path.join(BUILD, "gui-scripts", "lifecycle")
SHOTS = os.path.join(BUILD, "gui-shots")
ZIP = sorted(glob.glob(os.path.join(args.package_dir, "*.zip")))[-1]
REDRAW_WAIT_SECONDS = 10.0

redraws = [0]


def _count_redraw():
    redraws[0] += 1


def properties_area():
    for area in bpy.context.window_manager.windows[0].screen.areas:
        if area.type == 'PROPERTIES':
            return area
    raise RuntimeError("no Properties editor")


def redraw_everything():
    for area in bpy.context.window_manager.windows[0].screen.areas:
        area.tag_redraw()


def shown_faces(obj):
    return len(obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)


def after_redraws(count):
    """Steps to yield until the Properties editor has drawn count more times (or REDRAW_WAIT_SECONDS passed)."""
    start, waited = redraws[0], 0.0
    while redraws[0] < start + count and waited < REDRAW_WAIT_SECONDS:
        redraw_everything()
        yield 0.1
        waited += 0.1


def drawn_labels(obj):
    """The labels that the registered part of the modifier panel draws for obj's first modifier."""
    return support.drawn_labels(bpy.types.DATA_PT_loop_subdivision, obj.modifiers[0])


def screenshot(name):
    os.makedirs(SHOTS, exist_ok=True)
    path = os.path.join(SHOTS, f"addon_lifecycle_{name}.png")
    bpy.ops.screen.screenshot(filepath=path)
    return path


def install():
    """Installs the zip into the session's scripts folder, as Preferences ▸ Add-ons ▸ Install does."""
    bpy.ops.preferences.addon_install(filepath=ZIP, target='PREFS', overwrite=True)


def steps():
    shutil.rmtree(SCRIPTS, ignore_errors=True)
    os.makedirs(SCRIPTS)
    bpy.context.preferences.filepaths.script_directory = SCRIPTS
    bpy.utils.refresh_script_paths()
    install()
    bpy.ops.preferences.addon_enable(module=MODULE)
    check(MODULE in bpy.context.preferences.addons, f"the zip installs into {SCRIPTS} and the add-on turns on")
    bpy.types.SpaceProperties.draw_handler_add(_count_redraw, (), 'WINDOW', 'POST_PIXEL')
    cube = bpy.data.objects["Cube"]
    bpy.context.view_layer.objects.active = cube
    properties_area().spaces.active.context = 'MODIFIER'
    bpy.ops.object.loop_subdivision_add()
    yield from after_redraws(2)
    live = shown_faces(cube)
    check(live == 48, f"the default cube's entry shows its subdivision ({live} faces) in the Modifier tab")
    screenshot("added")

    def turn_off_and_on():
        bpy.ops.preferences.addon_disable(module=MODULE)
        return "turned off"

    def update_from_zip():
        bpy.ops.preferences.addon_disable(module=MODULE)
        install()  # newer files: their modification times make Blender reload the module on enabling
        return "updated from the zip"

    def reload_scripts():
        bpy.ops.script.reload()
        return "Reload Scripts"

    for action in (turn_off_and_on, update_from_zip, reload_scripts):
        what = action()
        yield from after_redraws(2)  # the Modifier tab is drawn with the add-on off (or just reloaded)
        if MODULE not in bpy.context.preferences.addons:
            check(shown_faces(cube) == 6, f"{what}: the entry shows its cage while the add-on is off")
            bpy.ops.preferences.addon_enable(module=MODULE)
        yield from after_redraws(2)
        faces = shown_faces(cube)
        check(faces == 48, f"{what}, then on: Blender keeps running and the entry is live again within two redraws "
                           f"({faces} faces)")
        labels = drawn_labels(cube)
        check(any("triangulated" in label for label in labels),
              f"{what}, then on: the modifier's panel draws the settings and notes again ({labels})")
        screenshot(action.__name__)
        bpy.context.view_layer.objects.active = cube
        cube.loop_subdivision.levels = 2
        yield from after_redraws(2)
        faces = shown_faces(cube)
        check(faces == 192, f"{what}: the panel's settings work again (level 2: {faces} faces)")
        cube.loop_subdivision.levels = 1
        yield from after_redraws(1)

    bpy.ops.preferences.addon_disable(module=MODULE)
    yield from after_redraws(2)
    check(shown_faces(cube) == 6 and not drawn_labels(cube),
          "turned off at the end: the cage is shown, and the kept part of the modifier's panel draws nothing")


support.run_in_interface(steps(), check)
