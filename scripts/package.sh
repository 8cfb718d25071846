#!/usr/bin/env bash
# Packs the Blender add-on (addon/'s Python files and the native modules scripts/build_modules.sh builds) as an
# installable zip: dist/loop_subdivision-<version>.zip. scripts/setup.sh runs it into build/dist/ after its build.
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
#
# Native modules: one per CPython ABI that Blender releases bundle (3.10: official 3.4-4.0; 3.11: Debian's 3.4 and
# official 4.1-5.0; 3.13: 5.1 and later), side by side, so that Python picks the matching one. They are
# built and checked by scripts/build_modules.sh (see there): with zig's clang for Blender's baseline, glibc 2.28, the
# C++ runtime linked in and hidden (no GLIBCXX_ or CXXABI_ symbol, only PyInit__loopsub exported), each imported in
# its interpreter, one line each with the newest GLIBC_ symbol it needs. An ABI with no interpreter here is skipped
# with a message, never silently. tests/package/test_modules.sh runs the Python tests against each staged module.
set -euo pipefail
cd "$(dirname "$0")/.."

out=dist
while (($#)); do
  case "$1" in
    --out) out="${2:?--out needs a directory}"; shift 2 ;;
    *) echo "package: unknown argument '$1' (usage: scripts/package.sh [--out DIR])" >&2; exit 2 ;;
  esac
done

# Staged beside the build trees, not in addon/: tests that run at the same time import addon/'s own module.
stage=build-package
rm -rf "$stage" && mkdir -p "$stage"
scripts/build_modules.sh "$stage"

# Python's zipfile (Debian's interpreter, which has tomllib) rather than the zip tool, which Debian does not install
# by default.
/usr/bin/python3 - "$out" "$stage" <<'EOF'
import os
import platform
import re
import sys
import tomllib
import zipfile

out, stage = sys.argv[1], sys.argv[2]


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
    # The development build's module stays out: the staged ones, built for each ABI, go in instead.
    files += [os.path.join(root, n) for n in sorted(names)
              if not n.startswith((".", "test_", "_loopsub")) and not n.endswith((".pyc", ".pyo"))]
modules = sorted(os.path.join(stage, n) for n in os.listdir(stage) if n.startswith("_loopsub") and n.endswith(".so"))
if not modules:
    fail(f"no native module (_loopsub*.so) in {stage}/")

os.makedirs(out, exist_ok=True)
path = os.path.join(out, f"{package}-{version}.zip")
with zipfile.ZipFile(path + ".part", "w", zipfile.ZIP_DEFLATED) as archive:
    for file in files:
        archive.write(file, os.path.join(package, os.path.relpath(file, "addon")))
    for module in modules:
        archive.write(module, os.path.join(package, os.path.basename(module)))
os.replace(path + ".part", path)
print(f"package: {len(files) + len(modules)} files in {path}")
EOF
