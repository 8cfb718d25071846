"""The Loop Subdivision entry of an object's modifier stack.

Blender lets no add-on register a modifier type, so the entry is a Geometry Nodes modifier named "Loop Subdivision"
that runs the node group of the same name: Object Info (original space) of a helper object, straight to the group
output. The helper is linked to no collection; it carries the latest subdivision as its mesh, which live.py writes.
Blender then does everything a modifier gets: the stack order, the viewport and render toggles, its own drawing and
rendering, Apply, undo and saving. A file opened where the add-on is missing still shows and renders the result it was
saved with, since that is ordinary mesh data.

Each helper names its owner, so a copied object (Shift D, Alt D), whose entry still points at the original's helper,
gets a helper of its own instead of showing the original's result.
"""
import bpy

from . import compat

ENTRY_NAME = "Loop Subdivision"
GROUP_TAG = "loop_subdivision"  # on the node group: the version of its layout
GROUP_VERSION = 1
OWNER_TAG = "loop_subdivision_owner"  # on a helper: the object whose entry it serves
RESULT_SOCKET = "Result"


def node_group():
    """The shared node group of every entry, made when the file has none."""
    for group in bpy.data.node_groups:
        if group.get(GROUP_TAG) == GROUP_VERSION:
            return group
    group = bpy.data.node_groups.new(ENTRY_NAME, 'GeometryNodeTree')
    group[GROUP_TAG] = GROUP_VERSION
    # Blender expects a geometry input first; the result replaces the geometry, so it stays unconnected.
    compat.add_group_socket(group, 'INPUT', 'NodeSocketGeometry', "Geometry")
    compat.add_group_socket(group, 'INPUT', 'NodeSocketObject', RESULT_SOCKET)
    compat.add_group_socket(group, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
    group_input = group.nodes.new('NodeGroupInput')
    info = group.nodes.new('GeometryNodeObjectInfo')
    info.transform_space = 'ORIGINAL'  # the helper's own coordinates are the owner's: no transform in between
    group_output = group.nodes.new('NodeGroupOutput')
    group_input.location, info.location, group_output.location = (-300, 0), (0, 0), (300, 0)
    group.links.new(group_input.outputs[RESULT_SOCKET], info.inputs["Object"])
    group.links.new(info.outputs["Geometry"], group_output.inputs["Geometry"])
    return group


def is_entry(modifier):
    group = modifier.node_group if modifier.type == 'NODES' else None
    return group is not None and group.get(GROUP_TAG) == GROUP_VERSION


def entry(obj):
    """The object's live entry: the first Loop Subdivision modifier in its stack, or None."""
    if obj is None or obj.type != 'MESH':
        return None
    return next((modifier for modifier in obj.modifiers if is_entry(modifier)), None)


def helper(obj, modifier, create=True):
    """The object that carries this entry's result; a new one when the entry has none of its own (None with
    create=False)."""
    current = compat.modifier_input(modifier, RESULT_SOCKET)
    if current is not None and current.get(OWNER_TAG) == obj:
        return current
    if not create:
        return None
    mesh = bpy.data.meshes.new(f"{obj.name} ({ENTRY_NAME})")
    carrier = bpy.data.objects.new(mesh.name, mesh)
    carrier[OWNER_TAG] = obj
    compat.set_modifier_input(modifier, RESULT_SOCKET, carrier)
    return carrier


def add(obj):
    """Adds an entry at the end of obj's stack, shown in Edit Mode too (as Subdivision Surface is)."""
    modifier = obj.modifiers.new(ENTRY_NAME, 'NODES')
    modifier.node_group = node_group()
    modifier.show_in_editmode = True
    helper(obj, modifier)
    return modifier


def is_first(obj, modifier):
    """Whether the entry comes first among the modifiers that act in the viewport (what Blender's Apply checks)."""
    enabled = [other for other in obj.modifiers if other.show_viewport]
    return not enabled or enabled[0] == modifier
