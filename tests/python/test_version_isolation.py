"""Every Blender-version difference goes through addon/compat.py: the add-on, the scripts and the benchmarks use none
of the APIs that differ between Blender 3.4 and 4.x directly. (Plain text search, no Blender needed.)"""
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
}

SOURCES = sorted(p for folder in ("addon", "scripts", "bench") for p in (ROOT / folder).glob("*.py")
                 if p.name != "compat.py")


def test_the_sources_are_found():
    names = {p.name for p in SOURCES}
    assert {"mesh_data.py", "live.py", "stack.py", "demo_blender.py"} <= names


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_no_version_specific_api_outside_compat(path):
    found = []
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        for pattern, what in VERSION_SPECIFIC.items():
            if re.search(pattern, line):
                found.append(f"{path.name}:{number}: {what}: {line.strip()}")
    assert not found, "use addon/compat.py instead:\n" + "\n".join(found)


def test_the_patterns_catch_what_they_name():
    # Each pattern matches the code it is there to keep out (so that a typo cannot make this test pass vacuously).
    samples = ["bm.edges.layers.crease.verify()", "mesh.use_auto_smooth = True", "len(mesh.vertex_creases)",
               "mesh.edges.foreach_set('crease', values)", 'mesh.polygons.foreach_set("loop_total", totals)',
               "group.inputs.new('NodeSocketGeometry', 'Geometry')", "bpy.types.DATA_PT_modifiers.append(f)",
               "gpu.shader.from_builtin('3D_UNIFORM_COLOR')"]
    for pattern, sample in zip(VERSION_SPECIFIC, samples):
        assert re.search(pattern, sample), (pattern, sample)
