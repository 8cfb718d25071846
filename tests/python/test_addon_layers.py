"""The add-on's folders are its layers (docs/addon.md, Layout of the package): each imports only from the layers under
it, and model/ imports no Blender module at all, so that tests import it with plain Python. (Plain text, no Blender
needed.)"""
import pathlib
import re

import pytest

ADDON = pathlib.Path(__file__).resolve().parents[2] / "addon"

# Each folder and the add-on's own modules it may import from ("native" is addon/native.py, the core's door).
MAY_IMPORT = {
    "model": set(),
    "blender": {"model", "blender"},
    "subdivision": {"model", "blender", "native", "subdivision"},
    "live": {"model", "blender", "native", "subdivision", "live"},
    "ui": {"model", "blender", "native", "subdivision", "live", "ui"},
}
BLENDER_MODULES = re.compile(r"^\s*(import|from)\s+(bpy|bmesh|mathutils|gpu)\b", re.M)
RELATIVE_IMPORT = re.compile(r"^\s*from\s+(\.+)([\w.]*)\s+import\s+(\([^)]*\)|[^\n#]+)", re.M)


def imported_layers(path):
    """The add-on's layers (top folders, or "native") that path imports by relative import."""
    folder = path.parent.name
    layers = set()
    for dots, module, names in RELATIVE_IMPORT.findall(path.read_text()):
        if len(dots) == 1:
            layers.add(folder)
        elif module:
            layers.add(module.split(".")[0])
        else:  # "from .. import native"
            layers.update(name.strip() for name in names.replace("(", "").replace(")", "").split(","))
    return layers


SOURCES = sorted(p for folder in MAY_IMPORT for p in (ADDON / folder).glob("*.py"))


def test_every_layer_is_found():
    assert {p.parent.name for p in SOURCES} == set(MAY_IMPORT)


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: f"{p.parent.name}/{p.name}")
def test_imports_only_from_layers_under_it(path):
    layers = imported_layers(path) - {""}
    assert layers <= MAY_IMPORT[path.parent.name], f"{path.parent.name}/{path.name} imports {sorted(layers)}"


@pytest.mark.parametrize("path", sorted((ADDON / "model").glob("*.py")), ids=lambda p: p.name)
def test_model_imports_no_blender_module(path):
    assert not BLENDER_MODULES.search(path.read_text()), f"model/{path.name} imports a Blender module"


def test_the_checks_catch_what_they_name():
    sample = ADDON / "blender" / "stack.py"
    assert "blender" in imported_layers(sample)
    assert BLENDER_MODULES.search("import bpy\n") and BLENDER_MODULES.search("from mathutils import Matrix\n")
    assert not {"live", "ui", "subdivision"} & imported_layers(sample)
