"""The zip of scripts/package.sh installs through Blender's add-on preferences and works from where it is installed.

Runs scripts/package.sh into a temporary folder, checks the zip's layout (one top-level folder named after the
manifest's id, holding __init__.py, blender_manifest.toml and the native module; no caches or tests), then starts a
second Blender whose user configuration and scripts live in a temporary folder, so the user's own are never touched.
That Blender installs the zip with preferences.addon_install, enables it with addon_enable and applies Loop
subdivision to a cube with the installed copy.
"""
import argparse
import os
import subprocess
import sys
import tempfile
import tomllib
import zipfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bpy  # noqa: E402

import blender_test_support as support  # noqa: E402

# The second Blender: installs, enables, then subdivides a cube (12 triangles once triangulated) to level 1.
INSTALL_SCRIPT = r"""
import sys
import addon_utils
import bpy

zip_path, module, scripts_dir = sys.argv[sys.argv.index("--") + 1:]
assert bpy.ops.preferences.addon_install(filepath=zip_path) == {'FINISHED'}, "addon_install failed"
assert bpy.ops.preferences.addon_enable(module=module) == {'FINISHED'}, "addon_enable failed"
loaded = sys.modules[module]
assert loaded.__file__.startswith(scripts_dir), f"{module} was loaded from {loaded.__file__}, not the install"
assert module in {m.__name__ for m in addon_utils.modules()} and addon_utils.check(module)[1], "not enabled"
bpy.ops.mesh.primitive_cube_add()
assert bpy.ops.object.loop_subdivision_apply(levels=1) == {'FINISHED'}, "apply failed"
faces = len(bpy.context.object.data.polygons)
assert faces == 48, f"a cube at level 1 has {faces} faces, expected 48"
print("INSTALLED-AND-APPLIED", loaded.__file__)
"""

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
parser = argparse.ArgumentParser()
parser.add_argument("--addon-dir", required=True)
repo = os.path.dirname(os.path.abspath(parser.parse_args(argv).addon_dir))
check = support.Check("test_package_install")

with open(os.path.join(repo, "addon", "blender_manifest.toml"), "rb") as f:
    manifest = tomllib.load(f)
package = manifest["id"]

with tempfile.TemporaryDirectory(prefix="loopsub-package-") as temp:
    dist = os.path.join(temp, "dist")
    packed = subprocess.run([os.path.join(repo, "scripts", "package.sh"), "--out", dist],
                            capture_output=True, text=True, timeout=600)
    print(packed.stdout + packed.stderr)
    zip_path = os.path.join(dist, f"{package}-{manifest['version']}.zip")
    check(packed.returncode == 0 and os.path.isfile(zip_path), f"scripts/package.sh wrote {zip_path}")

    with zipfile.ZipFile(zip_path) as archive:
        names = archive.namelist()
        check({name.split("/")[0] for name in names} == {package},
              f"one top-level folder, named after the manifest's id '{package}'")
        check({f"{package}/__init__.py", f"{package}/blender_manifest.toml"} <= set(names),
              "__init__.py (bl_info, Blender 3.4-4.1) and blender_manifest.toml (Blender 4.2+) at the folder's top")
        check(any(name.startswith(f"{package}/_loopsub") and name.endswith(".so") for name in names),
              "the native module is inside")
        check(not any("__pycache__" in name or name.endswith(".pyc") or "/tests/" in name
                      or os.path.basename(name).startswith("test_") for name in names),
              "no caches or tests")
        packed_manifest = tomllib.loads(archive.read(f"{package}/blender_manifest.toml").decode("utf-8"))
        check(packed_manifest == manifest, "the packed manifest parses and equals addon/blender_manifest.toml")

    config = os.path.join(temp, "config")
    scripts = os.path.join(temp, "scripts")
    environment = dict(os.environ, BLENDER_USER_CONFIG=config, BLENDER_USER_SCRIPTS=scripts)
    installed = subprocess.run(
        [bpy.app.binary_path, "--background", "--factory-startup", "--python-exit-code", "1",
         "--python-expr", INSTALL_SCRIPT, "--", zip_path, package, scripts],
        env=environment, capture_output=True, text=True, timeout=120)
    print(installed.stdout[-3000:] + installed.stderr[-3000:])
    check(installed.returncode == 0 and "INSTALLED-AND-APPLIED" in installed.stdout,
          "a Blender with an empty user configuration installs the zip, enables it, and its apply operator works")
    check(os.path.isfile(os.path.join(scripts, "addons", package, "__init__.py")),
          f"installed as scripts/addons/{package}/")

check.finish()
