"""Every Blender-version difference goes through addon/blender/ (Blender access, each difference once, in the module of
its concern): the rest of the add-on, the scripts and the benchmarks use none of the APIs that differ between Blender
3.4 and 4.x directly, nor branch on the version; and only addon/blender/memory_views.py reads or writes Blender's
memory by address. (Plain text search, no Blender needed.)"""
import pathlib
import re

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]

# API that exists only on some of the Blender versions the add-on supports, and what replaced it.
VERSION_SPECIFIC = {
    r"\blayers\.crease\b": "bmesh crease layers (gone in 4.0: float layers crease_edge / crease_vert)",
    r"\buse_auto_smooth\b|\bauto_smooth_angle\b": "Auto Smooth (gone in 4.1)",
    r"\bedge_creases\b|\bvertex_creases\b": "Mesh.edge_creases / vertex_creases (gone in 4.0)",
    r"foreach_(get|set)\(\s*[\"']crease[\"']": "MeshEdge.crease (gone in 4.0)",
    r"foreach_set\(\s*[\"']loop_total[\"']": "writing MeshPolygon.loop_total (read-only from 4.0)",
    r"\.(inputs|outputs)\.new\(\s*[\"']NodeSocket": "node group sockets (NodeTree.interface from 4.0)",
    r"\bDATA_PT_modifiers\b|\bOBJECT_MT_modifier_add": "the Add Modifier menu (a menu from 4.0)",
    r"[\"']3D_(UNIFORM|SMOOTH)_COLOR[\"']": "built-in shader names (renamed in 4.0)",
    r"\bbpy\.app\.version\s*[<>=!]": "a branch on Blender's version",
}
# Reading or writing Blender's memory by address, which addon/blender/memory_views.py alone does, under its contract.
BY_ADDRESS = r"\bas_pointer\(|\bfrom_address\(|\bctypeslib\b"

BLENDER_ACCESS = ROOT / "addon" / "blender"
SOURCES = sorted(p for folder in ("addon", "scripts", "bench") for p in (ROOT / folder).rglob("*.py")
                 if BLENDER_ACCESS not in p.parents)
ADDON = sorted(p for p in (ROOT / "addon").rglob("*.py") if p.name != "memory_views.py")


def test_the_sources_are_found():
    names = {p.name for p in SOURCES}
    assert {"engine.py", "cage.py", "panel.py", "demo_blender.py"} <= names and "stack.py" not in names
    assert {"stack.py", "mesh_arrays.py"} <= {p.name for p in ADDON}


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_version_specific_api_outside_blender_access(path):
    found = []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        for pattern, what in VERSION_SPECIFIC.items():
            if re.search(pattern, line):
                found.append(f"{path.name}:{number}: {what}: {line.strip()}")
    assert not found, "use addon/blender/ instead:\n" + "\n".join(found)


@pytest.mark.parametrize("path", ADDON, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_blender_memory_by_address_in_memory_views_alone(path):
    found = [f"{path.name}:{number}: {line.strip()}" for number, line in enumerate(path.read_text().splitlines(), 1)
             if re.search(BY_ADDRESS, line)]
    assert not found, "use addon/blender/memory_views.py instead:\n" + "\n".join(found)


def test_the_patterns_catch_what_they_name():
    # Each pattern matches the code it is there to keep out (so that a typo cannot make this test pass vacuously).
    samples = ["bm.edges.layers.crease.verify()", "mesh.use_auto_smooth = True", "len(mesh.vertex_creases)",
               "mesh.edges.foreach_set('crease', values)", 'mesh.polygons.foreach_set("loop_total", totals)',
               "group.inputs.new('NodeSocketGeometry', 'Geometry')", "bpy.types.DATA_PT_modifiers.append(f)",
               "gpu.shader.from_builtin('3D_UNIFORM_COLOR')", "if bpy.app.version >= (4, 0, 0):"]
    for pattern, sample in zip(VERSION_SPECIFIC, samples):
        assert re.search(pattern, sample), (pattern, sample)
    for sample in ("first = collection[0].as_pointer()", "(ctype * count).from_address(first)",
                   "np.ctypeslib.as_array(block)"):
        assert re.search(BY_ADDRESS, sample), sample
