"""The Loop Subdivision entry of an object's modifier stack.

Blender lets no add-on register a modifier type, so the entry is a Geometry Nodes modifier named "Loop Subdivision"
that runs the node group of the same name: Object Info (original space) of a helper object, straight to the group
output. The helper is linked to no collection; it carries the latest subdivision as its mesh, which live.py writes.
Blender then does everything a modifier gets: the stack order, the viewport and render toggles, its own drawing and
rendering, Apply, undo and saving. A file opened where the add-on is missing still shows and renders the result it was
saved with, since that is ordinary mesh data.

Each helper names its owner (the owner's name, a string: an ID pointer would be a user of the owner, which kept a
deleted object, its helper and its result alive and saved), so a copied object (Shift D, Alt D), whose entry still
points at the original's helper, gets a helper of its own instead of showing the original's result. A helper that no
live entry uses any more (its owner deleted, its entry removed or applied) is freed with its mesh by collect(), which
live.py runs after each update, before saving and after loading; an entry added again reuses its object's helper.
"""
import bpy

from . import compat

ENTRY_NAME = "Loop Subdivision"
GROUP_TAG = "loop_subdivision"  # on the node group: the version of its layout
GROUP_VERSION = 1
OWNER_TAG = "loop_subdivision_owner"  # on a helper: the name of the object whose entry it serves
RESULT_TAG = "loop_subdivision_result"  # on a helper's mesh (and the meshes that replaced it): made by the add-on
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


def is_helper(obj):
    return obj is not None and OWNER_TAG in obj


def owner_name(carrier):
    """The name of the object a helper serves. Files saved before the owner became a name hold the owner itself."""
    owner = carrier.get(OWNER_TAG)
    return owner.name if isinstance(owner, bpy.types.ID) else owner


def _serves(carrier, obj):
    """Whether carrier is (or may become) the helper of obj's entry: it names obj, or it names no object whose entry
    uses it (its owner was renamed, or deleted and a linked duplicate remains)."""
    name = owner_name(carrier)
    if name == obj.name:
        return True
    owner = bpy.data.objects.get(name) if isinstance(name, str) else None
    owner_entry = entry(owner) if owner is not None and owner != obj and owner.users else None
    return owner_entry is None or compat.modifier_input(owner_entry, RESULT_SOCKET) != carrier


def helper(obj, modifier, create=True):
    """The object that carries this entry's result; the object's unused helper, or a new one, when the entry has none
    of its own (None with create=False)."""
    current = compat.modifier_input(modifier, RESULT_SOCKET)
    if current is not None and is_helper(current) and _serves(current, obj):
        if current.get(OWNER_TAG) != obj.name and current.library is None:
            current[OWNER_TAG] = obj.name
        return current
    if not create:
        return None
    carrier = next((other for other in bpy.data.objects
                    if is_helper(other) and other.library is None and owner_name(other) == obj.name
                    and not other.users), None)
    if carrier is None:
        mesh = bpy.data.meshes.new(f"{obj.name} ({ENTRY_NAME})")
        mesh[RESULT_TAG] = True
        carrier = bpy.data.objects.new(mesh.name, mesh)
    carrier[OWNER_TAG] = obj.name
    compat.set_modifier_input(modifier, RESULT_SOCKET, carrier)
    return carrier


def _in_use():
    """The helpers that live entries use: those of the objects that have users (a deleted object that something
    else still holds has none in a scene, but keeps its helper while it exists)."""
    used = set()
    for obj in bpy.data.objects:
        if obj.type != 'MESH' or not obj.users:
            continue
        for modifier in obj.modifiers:
            if is_entry(modifier):
                carrier = compat.modifier_input(modifier, RESULT_SOCKET)
                if carrier is not None:
                    used.add(carrier.name_full)
    return used


def collect():
    """Frees what no live entry uses: helpers whose owner or entry is gone and their meshes, results with no user
    left (a render's replaced result), and the node group once no entry runs it. Returns how many IDs it removed."""
    removed = 0
    used = _in_use()
    for carrier in [obj for obj in bpy.data.objects if is_helper(obj) and obj.library is None]:
        if carrier.name_full in used:
            continue
        mesh = carrier.data
        bpy.data.objects.remove(carrier)
        removed += 1
        if mesh is not None and mesh.users == 0 and mesh.library is None:
            bpy.data.meshes.remove(mesh)
            removed += 1
    for mesh in [mesh for mesh in bpy.data.meshes if mesh.users == 0 and mesh.get(RESULT_TAG) and mesh.library is None]:
        bpy.data.meshes.remove(mesh)
        removed += 1
    for group in [group for group in bpy.data.node_groups
                  if group.get(GROUP_TAG) == GROUP_VERSION and group.users == 0 and group.library is None]:
        bpy.data.node_groups.remove(group)
        removed += 1
    return removed


def migrate():
    """Files saved while helpers held their owner as an ID pointer (a user of it): each becomes the owner's name, and
    an owner that only its helper kept alive (deleted, or a deleted linked duplicate that kept its mesh multi-user) is
    freed, as Blender would have freed it on deletion. Returns how many owners it freed."""
    owners = []
    for carrier in bpy.data.objects:
        owner = carrier.get(OWNER_TAG) if carrier.library is None else None
        if isinstance(owner, bpy.types.ID):
            carrier[OWNER_TAG] = owner.name
            owners.append(owner.name_full)
    freed = 0
    for name in owners:
        owner = bpy.data.objects.get(name)
        if owner is not None and owner.users == 0 and owner.library is None:
            mesh = owner.data if owner.type == 'MESH' else None
            bpy.data.objects.remove(owner)
            freed += 1
            if mesh is not None and mesh.users == 0 and mesh.library is None:
                bpy.data.meshes.remove(mesh)
    return freed


def add(obj):
    """Adds an entry at the end of obj's stack, shown in Edit Mode too (as Subdivision Surface is)."""
    modifier = obj.modifiers.new(ENTRY_NAME, 'NODES')
    modifier.node_group = node_group()
    modifier.show_in_editmode = True
    compat.hide_carrier_fields(modifier, RESULT_SOCKET)
    helper(obj, modifier)
    return modifier


# What Blender names a new Geometry Nodes modifier; a duplicate of an entry (the modifier's menu ▸ Duplicate,
# object.modifier_copy) gets it in 3.4.1 and 4.2.23 (4.5 and later keep the name, "Loop Subdivision.001").
_NODES_DEFAULT_NAME = "GeometryNodes"


def tidy(obj):
    """Every Loop Subdivision modifier of obj named as one, its carrier's own fields hidden (compat): a duplicated
    entry comes named "GeometryNodes" in some versions, and entries of files saved before the fields were hidden
    show them. Changes nothing that is right already (the depsgraph handler runs this). Returns the renamed ones."""
    renamed = []
    if obj is None or obj.type != 'MESH' or obj.library is not None:
        return renamed
    for modifier in obj.modifiers:
        if not is_entry(modifier):
            continue
        name = modifier.name
        if name == _NODES_DEFAULT_NAME or (name.startswith(_NODES_DEFAULT_NAME + ".")
                                           and name[len(_NODES_DEFAULT_NAME) + 1:].isdigit()):
            modifier.name = ENTRY_NAME  # Blender makes it unique in the stack ("Loop Subdivision.001")
            renamed.append(modifier)
        if modifier.node_group.library is None:
            compat.hide_carrier_fields(modifier, RESULT_SOCKET)
    return renamed


def is_first(obj, modifier):
    """Whether the entry comes first among the modifiers that act in the viewport (what Blender's Apply checks)."""
    enabled = [other for other in obj.modifiers if other.show_viewport]
    return not enabled or enabled[0] == modifier
