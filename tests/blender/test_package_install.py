"""The zip of scripts/package.sh installs as users install it and works from where it is installed.

The zip is the one scripts/setup.sh packed (--package-dir). Its layout is checked (one top-level folder named after
the manifest's id, holding __init__.py, blender_manifest.toml and a native module for each CPython that Blender
bundles; no caches or tests). Then a second Blender, whose user folders live in a temporary folder so that the user's
own are never touched, installs it the way its version offers:
- Blender 3.4 to 4.1: Preferences ▸ Add-ons ▸ Install (preferences.addon_install, addon_enable), as a legacy add-on.
- Blender 4.2+: Get Extensions ▸ Install from Disk (extensions.package_install_files), as an extension, after
  Blender's own validator (`blender --command extension validate`, the bl_pkg code every 4.2+ ships) accepted the
  zip; the installed extension shows the manifest's name and version (its bl_info must not override them).
Either way the installed copy, not the source tree, applies Loop subdivision to a cube.
"""
import argparse
import glob
import os
import subprocess
import sys
import tempfile
import tomllib
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

IS_EXTENSION = bpy.app.version >= (4, 2, 0)

# The second Blender: installs, enables, then subdivides a cube (12 triangles once triangulated) to level 1.
INSTALL_SCRIPT = r"""
import os, sys
import addon_utils
import bpy

zip_path, package, user_dir, is_extension, name, version, tagline = sys.argv[sys.argv.index("--") + 1:]
""" + support.exiting_script(r"""
    if is_extension == "1":
        result = bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default",
                                                          enable_on_install=True)
        assert result == {'FINISHED'}, f"package_install_files: {result}"
        module = f"bl_ext.user_default.{package}"
    else:
        assert bpy.ops.preferences.addon_install(filepath=zip_path) == {'FINISHED'}, "addon_install failed"
        assert bpy.ops.preferences.addon_enable(module=package) == {'FINISHED'}, "addon_enable failed"
        module = package
    loaded = sys.modules[module]
    assert os.path.realpath(loaded.__file__).startswith(os.path.realpath(user_dir)), \
        f"{module} was loaded from {loaded.__file__}, not from the user folder {user_dir}"
    assert addon_utils.check(module)[1], f"{module} is not enabled"
    info = addon_utils.module_bl_info(loaded)
    shown = (info["name"], ".".join(str(part) for part in info["version"]))
    assert shown == (name, version), f"Blender shows the add-on as {shown}, the package says {(name, version)}"
    if is_extension == "1":  # the manifest's tagline is what Preferences shows, not bl_info's older description
        assert info["description"] == tagline, f"Blender shows {info['description']!r}, the manifest {tagline!r}"
    bpy.ops.mesh.primitive_cube_add()
    assert bpy.ops.object.loop_subdivision_apply(levels=1) == {'FINISHED'}, "apply failed"
    faces = len(bpy.context.object.data.polygons)
    assert faces == 48, f"a cube at level 1 has {faces} faces, expected 48"
    print("INSTALLED-AND-APPLIED", loaded.__file__)

    # With an entry in the scene: turned off and on, then updated (the zip installed again over itself, which
    # rewrites the installed native module in 3.4), as an artist does from Preferences. The entry is live again at
    # the next update of the scene, and the part of the modifier panel draws with the new code.
    bpy.ops.mesh.primitive_cube_add(location=(4.0, 0.0, 0.0))
    cube = bpy.context.object
    assert bpy.ops.object.loop_subdivision_add(levels=1) == {'FINISHED'}, "add failed"

    def shown_faces():
        cube.location.x += 1.0
        depsgraph = bpy.context.evaluated_depsgraph_get()
        return len(cube.evaluated_get(depsgraph).data.polygons)

    for step in ("turned off and on", "updated from the zip"):
        assert shown_faces() == 48, f"before being {step}: the entry shows its subdivision"
        bpy.ops.preferences.addon_disable(module=module)
        assert shown_faces() == 6, f"{step}: while off, the entry shows its cage"
        if step == "updated from the zip" and is_extension == "1":
            bpy.ops.extensions.package_install_files(filepath=zip_path, repo="user_default", enable_on_install=True)
        else:
            if step == "updated from the zip":
                assert bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True) == {'FINISHED'}
            assert bpy.ops.preferences.addon_enable(module=module) == {'FINISHED'}, "addon_enable failed"
        faces = shown_faces()
        assert faces == 48, f"{step}: the entry is live again at the next update ({faces} faces)"
        draw = bpy.types.DATA_PT_loop_subdivision.draw
        assert draw is sys.modules[module + ".ui.panel"]._draw_entry, f"{step}: the panel draws with {draw}"
    print("TURNED-OFF-ON-AND-UPDATED")
""")

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--package-dir", required=True)
args, _ = parser.parse_known_args(argv)
repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
check = support.Check("test_package_install")

with open(os.path.join(repo, "addon", "blender_manifest.toml"), "rb") as f:
    manifest = tomllib.load(f)
package = manifest["id"]
zip_path = os.path.join(args.package_dir, f"{package}-{manifest['version']}.zip")
check(os.path.isfile(zip_path), f"scripts/package.sh wrote {zip_path}")

with zipfile.ZipFile(zip_path) as archive:
    names = archive.namelist()
    check({name.split("/")[0] for name in names} == {package},
          f"one top-level folder, named after the manifest's id '{package}'")
    check({f"{package}/__init__.py", f"{package}/blender_manifest.toml"} <= set(names),
          "__init__.py (bl_info, Blender 3.4-4.1) and blender_manifest.toml (Blender 4.2+) at the folder's top")
    modules = sorted(os.path.basename(name) for name in names
                     if name.startswith(f"{package}/_loopsub") and name.endswith(".so"))
    abis = {module.split(".")[1].split("-")[1] for module in modules}
    check({"310", "311", "313"} <= abis,
          f"native modules for CPython 3.10 (Blender 3.4-4.0), 3.11 (4.1-5.0) and 3.13 (5.1+): {modules}")
    check(not any("__pycache__" in name or name.endswith(".pyc") or "/tests/" in name
                  or os.path.basename(name).startswith("test_") for name in names),
          "no caches or tests")
    packed_manifest = tomllib.loads(archive.read(f"{package}/blender_manifest.toml").decode("utf-8"))
    check(packed_manifest == manifest, "the packed manifest parses and equals addon/blender_manifest.toml")

if IS_EXTENSION:
    # Blender's own validator, as `blender --command extension validate` runs it (the same script in every 4.2+).
    validator = os.path.join(bpy.utils.system_resource('SCRIPTS'), "addons_core", "bl_pkg", "cli", "blender_ext.py")
    validated = subprocess.run([sys.executable if not bpy.app.binary_path else bpy.app.binary_path]
                               + (["--command", "extension", "validate"] if bpy.app.binary_path
                                  else [validator, "validate"]) + [zip_path],
                               capture_output=True, text=True, timeout=120)
    print(validated.stdout[-2000:] + validated.stderr[-2000:])
    check(validated.returncode == 0 and "error" not in (validated.stdout + validated.stderr).lower(),
          f"Blender {bpy.app.version_string}'s extension validator accepts the zip")

with tempfile.TemporaryDirectory(prefix="loopsub-package-") as temp:
    # Every user folder in the temporary one: configuration, scripts (legacy add-ons), extensions (4.2+).
    environment = dict(os.environ, BLENDER_USER_CONFIG=os.path.join(temp, "config"),
                       BLENDER_USER_SCRIPTS=os.path.join(temp, "scripts"),
                       BLENDER_USER_EXTENSIONS=os.path.join(temp, "extensions"),
                       BLENDER_USER_RESOURCES=temp)
    install_args = ["--", zip_path, package, temp, "1" if IS_EXTENSION else "0", manifest["name"],
                    manifest["version"], manifest["tagline"]]
    if bpy.app.binary_path:
        command = [bpy.app.binary_path, "--background", "--factory-startup", "--python-expr", INSTALL_SCRIPT]
    else:
        command = [sys.executable, "-c", "import bpy\n" + INSTALL_SCRIPT]
    installed = subprocess.run(command + install_args, env=environment, capture_output=True, text=True, timeout=120)
    print(installed.stdout[-3000:] + installed.stderr[-3000:])
    where = "an extension (Install from Disk)" if IS_EXTENSION else "a legacy add-on (Install…)"
    check(installed.returncode == 0 and "INSTALLED-AND-APPLIED" in installed.stdout,
          f"a Blender with empty user folders installs the zip as {where}, shows the manifest's name, version "
          "and tagline (4.2+), enables it, and its apply operator works")
    check(installed.returncode == 0 and "TURNED-OFF-ON-AND-UPDATED" in installed.stdout,
          "with an entry in the scene, the add-on turned off and on, and updated from the zip, leaves Blender "
          "running and the entry live")
    installed_init = glob.glob(os.path.join(temp, "**", package, "__init__.py"), recursive=True)
    check(len(installed_init) == 1, f"installed once, under the temporary user folders: {installed_init}")

check.finish()
