"""Edit Mode with a Loop Subdivision entry in Blender's interface (Debian's Blender 3.4.1 under Xvfb): the entry's
result is drawn with the cage over it, and turning on "Adjust edit cage to modifier result" (On Cage, in the
modifier's header) keeps the cage drawn, and selectable, as it is: the toggle goes off again and the status bar says
why. (Blender draws the cage onto a modifier's result by original indices, which the add-on's result cannot carry:
with the toggle on, no vertex or edge was drawn.)

Run as ctest's gui.test_edit_mode: `xvfb-run blender --factory-startup --python THIS -- --addon-dir DIR`. Steps run
from a timer, as an artist's actions arrive between redraws; the screenshot goes to build/gui-shots/.
"""
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "blender"))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

addon = support.load_addon()
bpy.context.preferences.view.show_splash = False  # now, before Blender opens it over the window
check = support.Check("test_edit_mode")
# build/packaged-addon/loop_subdivision/__init__.py -> build/gui-shots
SHOTS = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(addon.__file__)))), "gui-shots")


def view_3d():
    for area in bpy.context.window_manager.windows[0].screen.areas:
        if area.type == 'VIEW_3D':
            return area
    raise RuntimeError("no 3D Viewport")


def steps():
    window = bpy.context.window_manager.windows[0]
    cube = bpy.data.objects["Cube"]
    support.select_only(cube)
    bpy.ops.object.loop_subdivision_add(levels=2)
    modifier = addon.blender.stack.entry(cube)
    area = view_3d()
    region = next(region for region in area.regions if region.type == 'WINDOW')
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.object.mode_set(mode='EDIT')
        bpy.ops.mesh.select_all(action='SELECT')
        bpy.ops.view3d.view_selected()
    yield 1.0
    modifier.show_on_cage = True  # what a click on the header's toggle sets
    area.tag_redraw()
    yield 1.0
    check(not modifier.show_on_cage, "On Cage turned on in Edit Mode goes off again")
    faces = len(cube.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.polygons)
    check(faces == 12 * 16, f"the result is still shown in Edit Mode ({faces} faces)")
    os.makedirs(SHOTS, exist_ok=True)
    path = os.path.join(SHOTS, "edit_mode_on_cage.png")
    bpy.ops.screen.screenshot(filepath=path)
    check(os.path.isfile(path), f"a screenshot of the cage drawn over the result: {path}")
    yield 0.2


support.run_in_interface(steps(), check)
