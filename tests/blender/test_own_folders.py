"""This Blender, started exactly as every Blender test starts (tests/own_folders.sh), keeps its temporary folder and
user folders in the build tree and changes nothing of the machine's: not /tmp/copybuffer.blend, the copy buffer that
the artist's own Blender pastes from (a test run once replaced it with a 5.3 file, and Ctrl V in 3.4.1 failed with "not
a blend file"), nor ~/.config/blender/.

Checked here: Python's and Blender's temporary folders (tempfile.gettempdir(), bpy.app.tempdir) and Blender's user
folders (resource_path('USER'), user_resource CONFIG, SCRIPTS, DATAFILES, EXTENSIONS in 4.2+) are in the build tree
(the one holding --addon-dir); Ctrl C (view3d.copybuffer) of a selected object writes copybuffer.blend into the
build tree's temporary folder, and Ctrl V pastes it back; a second Blender started as the tests start them
(support.run_blender: the program, or this interpreter importing bpy) does the same there. Through all of it
/tmp/copybuffer.blend and everything under ~/.config/blender/ and ~/.cache/thumbnails/ (where Blender puts the thumbnail
of each file it saves) stay as they were (or absent).
"""
import argparse
import os
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)  # build/packaged-addon/loop_subdivision
args, _ = parser.parse_known_args(argv)
check = support.Check("test_own_folders")
BUILD = os.path.realpath(os.path.dirname(os.path.dirname(os.path.abspath(args.addon_dir))))
MACHINE_COPY_BUFFER = "/tmp/copybuffer.blend"
# The user's Blender folders, and the thumbnails Blender writes for every file it saves (~/.cache/thumbnails/).
USER_FOLDERS = [os.path.expanduser(path) for path in ("~/.config/blender", "~/.cache/thumbnails")]


def in_build(path):
    return bool(path) and os.path.realpath(path).startswith(BUILD + os.sep)


def snapshot():
    """(path, inode, size, mtime) of the machine's copy buffer and of everything in the user's Blender folders."""
    paths = [MACHINE_COPY_BUFFER] + USER_FOLDERS
    for folder in USER_FOLDERS:
        for root, folders, files in os.walk(folder):
            paths += [os.path.join(root, name) for name in folders + files]
    state = {}
    for path in paths:
        try:
            status = os.lstat(path)
        except FileNotFoundError:
            continue
        state[path] = (status.st_ino, status.st_size, status.st_mtime_ns)
    return state


def changes(before, after):
    return sorted(path for path in set(before) | set(after) if before.get(path) != after.get(path))


before = snapshot()
print(f"  (build tree {BUILD}; Blender {bpy.app.version_string}, "
      f"{'the program' if bpy.app.binary_path else 'a Python module'})")

check(in_build(tempfile.gettempdir()), f"Python's temporary folder is in the build tree: {tempfile.gettempdir()}")
check(in_build(bpy.app.tempdir), f"Blender's temporary folder is in the build tree: {bpy.app.tempdir}")
user_folders = {"USER": bpy.utils.resource_path('USER')}
kinds = ("CONFIG", "SCRIPTS", "DATAFILES") + (("EXTENSIONS",) if bpy.app.version >= (4, 2, 0) else ())
for kind in kinds:
    user_folders[kind] = bpy.utils.user_resource(kind)
for kind, path in user_folders.items():
    check(in_build(path), f"Blender's user folder {kind} is in the build tree: {path}")

# Ctrl C: the copy buffer is the temporary folder's base (bpy.app.tempdir is this session's folder inside it).
copy_buffer = os.path.join(os.path.dirname(os.path.normpath(bpy.app.tempdir)), "copybuffer.blend")
support.clear_scene()
obj = support.object_from_bmesh("Copied", support.cube("Copied"))
support.select_only(obj)
check(bpy.ops.view3d.copybuffer() == {'FINISHED'}, "Ctrl C (view3d.copybuffer) of a selected cube")
check(in_build(copy_buffer) and os.path.isfile(copy_buffer),
      f"the copy buffer is written in the build tree: {copy_buffer} "
      f"({'there' if os.path.isfile(copy_buffer) else 'absent'})")
support.clear_scene()
check(bpy.ops.view3d.pastebuffer() == {'FINISHED'} and "Copied" in bpy.data.objects,
      "Ctrl V (view3d.pastebuffer) pastes the cube back from it")

# A second Blender, as the tests start them (test_files, test_memory_limit, ...): it inherits this one's folders.
blend = os.path.join(tempfile.mkdtemp(), "copied.blend")
bpy.ops.wm.save_as_mainfile(filepath=blend)  # and its thumbnail into XDG_CACHE_HOME/thumbnails/
SECOND = r"""
import os, tempfile
import bpy
obj = bpy.data.objects["Copied"]
for other in bpy.context.view_layer.objects:
    other.select_set(other == obj)
bpy.context.view_layer.objects.active = obj
assert bpy.ops.view3d.copybuffer() == {'FINISHED'}, "copybuffer"
print("SECOND-TEMP", bpy.app.tempdir)
print("SECOND-PYTHON-TEMP", tempfile.gettempdir())
print("SECOND-USER", bpy.utils.resource_path('USER'))
"""
code, output = support.run_blender(blend, SECOND, timeout=300)
reported = dict(line.split(" ", 1) for line in output.splitlines()
                if line.startswith(("SECOND-TEMP ", "SECOND-PYTHON-TEMP ", "SECOND-USER ")))
if not check(code == 0 and len(reported) == 3, "a second Blender opens the file and copies the cube (Ctrl C)"):
    print(output[-3000:])
for key, what in (("SECOND-TEMP", "temporary folder"), ("SECOND-PYTHON-TEMP", "Python temporary folder"),
                  ("SECOND-USER", "user folders")):
    check(in_build(reported.get(key)), f"the second Blender's {what} is in the build tree: {reported.get(key)}")

changed = changes(before, snapshot())
check(not changed, f"{MACHINE_COPY_BUFFER}, ~/.config/blender/ and ~/.cache/thumbnails/ are as they were: "
      f"changed {changed}")

check.finish()
