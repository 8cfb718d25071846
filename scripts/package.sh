#!/usr/bin/env bash
# Packs the Blender add-on (addon/ with the native module built into it) as an installable zip:
# dist/loop_subdivision-<version>.zip. Sets the project up first (scripts/setup.sh) when the module is not built.
#
# Usage: scripts/package.sh [--out DIR]   (default dist/; prints the zip's path)
#
# Layout: the zip holds one folder, loop_subdivision/, with __init__.py, blender_manifest.toml and the rest of the
# package. It serves both installers:
#  - Blender 3.4 to 4.1 (Preferences ▸ Add-ons ▸ Install) extract the zip into scripts/addons/ as it is, so the zip
#    must contain the package folder; its name becomes the module name, found by its __init__.py and bl_info.
#  - Blender 4.2+ (Get Extensions ▸ Install from Disk) read blender_manifest.toml either at the root of the zip or
#    inside a single top-level folder (both are documented); it installs the package under the manifest's id.
#    The folder is named after that id, so both versions install the same package name.
set -euo pipefail
cd "$(dirname "$0")/.."

out=dist
while (($#)); do
  case "$1" in
    --out) out="${2:?--out needs a directory}"; shift 2 ;;
    *) echo "package: unknown argument '$1' (usage: scripts/package.sh [--out DIR])" >&2; exit 2 ;;
  esac
done

if ! compgen -G "addon/_loopsub*.so" >/dev/null; then
  echo "package: the native module is not built into addon/: running scripts/setup.sh"
  scripts/setup.sh
fi

# Python's zipfile (Debian's interpreter, the one the build targets, which has tomllib) rather than the zip tool,
# which Debian does not install by default.
/usr/bin/python3 - "$out" <<'EOF'
import os
import platform
import re
import sys
import tomllib
import zipfile

out = sys.argv[1]


def fail(message):
    sys.exit(f"package: {message}")


with open("addon/blender_manifest.toml", "rb") as f:
    manifest = tomllib.load(f)
package, version = manifest["id"], manifest["version"]

# bl_info (Blender 3.4 to 4.1) and the manifest (4.2+) must announce the same version.
with open("addon/__init__.py", encoding="utf-8") as f:
    match = re.search(r'"version"\s*:\s*\((\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*\)', f.read())
if match is None:
    fail("no version in addon/__init__.py's bl_info")
if ".".join(match.groups()) != version:
    fail(f"bl_info's version {'.'.join(match.groups())} differs from blender_manifest.toml's {version}")

# The manifest's platforms must name the platform the native module was built for, this machine's.
machine = {"x86_64": "x64", "amd64": "x64", "aarch64": "arm64", "arm64": "arm64"}.get(platform.machine().lower())
built_for = f"{sys.platform.replace('darwin', 'macos').replace('win32', 'windows')}-{machine}"
if built_for not in manifest.get("platforms", []):
    fail(f"blender_manifest.toml's platforms {manifest.get('platforms')} do not name {built_for}, "
         "the platform of the native module built here")

files = []
for root, dirs, names in os.walk("addon"):
    # Caches and tests stay out of the product; so do hidden files (editor and tool state).
    dirs[:] = sorted(d for d in dirs if d not in ("__pycache__", "tests") and not d.startswith("."))
    files += [os.path.join(root, n) for n in sorted(names)
              if not n.startswith(".") and not n.endswith((".pyc", ".pyo")) and not n.startswith("test_")]
if not any(os.path.basename(f).startswith("_loopsub") and f.endswith(".so") for f in files):
    fail("no native module (_loopsub*.so) in addon/")

os.makedirs(out, exist_ok=True)
path = os.path.join(out, f"{package}-{version}.zip")
with zipfile.ZipFile(path + ".part", "w", zipfile.ZIP_DEFLATED) as archive:
    for file in files:
        archive.write(file, os.path.join(package, os.path.relpath(file, "addon")))
os.replace(path + ".part", path)
print(f"package: {len(files)} files in {path}")
EOF
