"""The Loop Subdivision entry of an object's modifier stack.

Blender lets no add-on register a modifier type, so the entry is a Geometry Nodes modifier named "Loop Subdivision"
that runs the node group of the same name: Object Info (original space) of a helper object, straight to the group
output. The helper is linked to no collection; it carries the latest subdivision as its mesh, which live.py writes.
Blender then does everything a modifier gets: the stack order, the viewport and render toggles, its own drawing and
rendering, Apply, undo and saving. Files hold no results unless asked to (live.py's save handler points the entries at
an empty placeholder meanwhile): where the add-on is missing, the node group shows the cage; a stored result is
ordinary mesh data, which such a Blender shows and renders.

Each helper names its owner (the owner's name, a string: an ID pointer would be a user of the owner, which kept a
deleted object, its helper and its result alive and saved), so a copied object (Shift D, Alt D), whose entry still
points at the original's helper, gets a helper of its own instead of showing the original's result. A helper that no
live entry uses any more (its owner deleted, its entry removed or applied) is freed with its mesh by collect(), which
live.py runs after each update, before saving and after loading; an entry added again reuses its object's helper.
"""
import bpy
import numpy as np

from . import mesh_arrays, node_group
from .node_group import (BASE_INPUT_ATTRIBUTE, BASE_SOCKET, ENTRY_NAME, GROUP_TAG, GROUP_VERSION, GROUP_VERSIONS,
                         RESULT_SOCKET, SOCKETS)

OWNER_TAG = "loop_subdivision_owner"  # on a helper: the name of the object whose entry it serves
BASE_TAG = "loop_subdivision_base"  # on a helper of the Base Result
BASE_COUNTS_TAG = "loop_subdivision_base_counts"  # on it: the points and faces of the mesh it was made from
RESULT_TAG = "loop_subdivision_result"  # on a helper's mesh (and the meshes that replaced it): made by the add-on

# A file saved without its results (the default; Object.loop_subdivision.store_result keeps them) points every entry
# at one empty object of this name: where the add-on is missing the entry shows the cage, and its panel shows this
# name in the Result field under the node group's name, "Loop Subdivision" (3.4 to 4.2; 4.3+ show a warning from the
# node group besides). Short enough to be read whole in that field at the default width of the Properties editor
# (3.4.1: ten characters; a longer name was cut to "Enable t…").
PLACEHOLDER_NAME = "Add-on off"
PLACEHOLDER_TAG = "loop_subdivision_placeholder"


def is_entry(modifier):
    group = modifier.node_group if modifier.type == 'NODES' else None
    return group is not None and group.get(GROUP_TAG) in GROUP_VERSIONS


def entry(obj):
    """The object's live entry: the first Loop Subdivision modifier in its stack, or None."""
    if obj is None or obj.type != 'MESH':
        return None
    return next((modifier for modifier in obj.modifiers if is_entry(modifier)), None)


def is_helper(obj):
    return obj is not None and OWNER_TAG in obj


def owner_name(helper):
    """The name of the object a helper serves. Files saved before the owner became a name hold the owner itself."""
    owner = helper.get(OWNER_TAG)
    return owner.name if isinstance(owner, bpy.types.ID) else owner


def _serves(helper, obj, socket):
    """Whether helper is (or may become) the helper of obj's entry at socket: it names obj, or it names no object
    whose entry uses it (its owner was renamed, or deleted and a linked duplicate remains)."""
    name = owner_name(helper)
    if name == obj.name:
        return True
    owner = bpy.data.objects.get(name) if isinstance(name, str) else None
    owner_entry = entry(owner) if owner is not None and owner != obj and owner.users else None
    return owner_entry is None or modifier_input(owner_entry, socket) != helper


def helper_of(obj, modifier, create=True, socket=RESULT_SOCKET):
    """The object that carries this entry's result (or, at BASE_SOCKET, its Base Result); the object's unused helper
    of that kind, or a new one, when the entry has none of its own (None with create=False)."""
    current = modifier_input(modifier, socket)
    if current is not None and is_helper(current) and _serves(current, obj, socket):
        if current.get(OWNER_TAG) != obj.name and current.library is None:
            current[OWNER_TAG] = obj.name
        return current
    if not create:
        return None
    base = socket == BASE_SOCKET
    helper = next((other for other in bpy.data.objects
                    if is_helper(other) and other.library is None and owner_name(other) == obj.name
                    and bool(other.get(BASE_TAG)) == base and not other.users), None)
    if helper is None:
        mesh = bpy.data.meshes.new(f"{obj.name} ({socket if base else ENTRY_NAME})")
        mesh[RESULT_TAG] = True
        helper = bpy.data.objects.new(mesh.name, mesh)
        if base:
            helper[BASE_TAG] = True
    helper[OWNER_TAG] = obj.name
    set_modifier_input(modifier, socket, helper)
    return helper


def keep_base_input(helper, mesh):
    """Marks the Base helper's mesh as made from `mesh` (the object's own): its vertex positions in the first points
    (node_group.build_nodes compares the input with them), and its number of points and faces."""
    positions = mesh_arrays.read_positions(mesh)
    result = helper.data
    kept = np.zeros((len(result.vertices), 3), dtype=np.float32)
    count = min(len(positions), len(kept))
    kept[:count] = positions[:count]
    attribute = result.attributes.get(BASE_INPUT_ATTRIBUTE)
    if attribute is None:
        attribute = result.attributes.new(BASE_INPUT_ATTRIBUTE, 'FLOAT_VECTOR', 'POINT')
    attribute.data.foreach_set("vector", kept.ravel())
    helper[BASE_COUNTS_TAG] = (len(positions), len(mesh.polygons))


def show_base(helper, shown):
    """Whether the node group may show the Base Result (where its input is the mesh it was made from), kept in the
    helper's location, which Object Info in original space does not move the geometry by: x the number of points of
    that mesh, or 0 where it may not (the stack's input is that mesh in points, positions and faces, as a rig at rest
    makes it: the result of the stack then shows, at Render levels in renders), y its number of faces (exact up to
    2^24)."""
    points, faces = helper.get(BASE_COUNTS_TAG, (0, 0)) if shown else (0, 0)
    if tuple(helper.location[:2]) != (points, faces):
        helper.location[:2] = (points, faces)


def placeholder():
    """The empty object that entries point at in a file saved without its results (PLACEHOLDER_NAME)."""
    for obj in bpy.data.objects:
        if obj.get(PLACEHOLDER_TAG) and obj.library is None:
            return obj
    mesh = bpy.data.meshes.new(PLACEHOLDER_NAME)
    mesh[RESULT_TAG] = True
    obj = bpy.data.objects.new(PLACEHOLDER_NAME, mesh)
    obj[PLACEHOLDER_TAG] = True
    return obj


def _in_use():
    """The helpers that live entries use: those of the objects that have users (a deleted object that something
    else still holds has none in a scene, but keeps its helper while it exists)."""
    used = set()
    for obj in bpy.data.objects:
        if obj.type != 'MESH' or not obj.users:
            continue
        for modifier in obj.modifiers:
            if is_entry(modifier):
                for socket in SOCKETS:
                    helper = modifier_input(modifier, socket)
                    if helper is not None:
                        used.add(helper.name_full)
    return used


def collect():
    """Frees what no live entry uses: helpers whose owner or entry is gone and their meshes, results with no user
    left (a render's replaced result), the placeholder of a file saved without results once no entry points at it,
    and the node group once no entry runs it. Returns how many IDs it removed."""
    removed = 0
    used = _in_use()
    # Found unused by what entries point at, not by user counts: 5.2.3 keeps counting a user of an object that a
    # modifier input pointed at before (modifier.properties.inputs).
    for helper in [obj for obj in bpy.data.objects
                    if (is_helper(obj) or obj.get(PLACEHOLDER_TAG)) and obj.library is None]:
        if helper.name_full in used:
            continue
        mesh = helper.data
        _forget_phantom_users(helper)
        bpy.data.objects.remove(helper)
        removed += 1
        if mesh is not None and mesh.users == 0 and mesh.library is None:
            bpy.data.meshes.remove(mesh)
            removed += 1
    for mesh in [mesh for mesh in bpy.data.meshes if mesh.users == 0 and mesh.get(RESULT_TAG) and mesh.library is None]:
        bpy.data.meshes.remove(mesh)
        removed += 1
    for group in [group for group in bpy.data.node_groups
                  if group.get(GROUP_TAG) in GROUP_VERSIONS and group.users == 0 and group.library is None]:
        bpy.data.node_groups.remove(group)
        removed += 1
    return removed


def _forget_phantom_users(helper):
    """Clears the users Blender counts for a helper that nothing uses: a duplicate of an entry (object.modifier_copy)
    counts one user of its helper that its removal, or Convert ▸ Mesh, does not give back (3.4.1), and removing a
    helper that still counts one prints an error on the console."""
    if helper.users and not bpy.data.user_map(subset=[helper])[helper]:
        helper.user_clear()


def unlink_helpers():
    """Takes helpers out of the collections a paste or an append linked them into (Blender links every object of a
    copy buffer or a library that no collection holds into the active one), where they showed the result a second
    time, beside their entry's. Returns how many it took out."""
    unlinked = 0
    for helper in bpy.data.objects:
        if not is_helper(helper) or helper.library is not None:
            continue
        for collection in helper.users_collection:
            if collection.library is None:
                collection.objects.unlink(helper)
                unlinked += 1
    return unlinked


def migrate():
    """Files saved by earlier versions of the add-on: node groups of an older layout get the current one; helpers
    that held their owner as an ID pointer (a user of it) get the owner's name, and an owner that only its helper
    kept alive (deleted, or a deleted linked duplicate that kept its mesh multi-user) is freed, as Blender would have
    freed it on deletion. Returns how many owners it freed."""
    owners = []
    for helper in bpy.data.objects:
        owner = helper.get(OWNER_TAG) if helper.library is None else None
        if isinstance(owner, bpy.types.ID):
            helper[OWNER_TAG] = owner.name
            owners.append(owner.name_full)
    for group in bpy.data.node_groups:
        if group.get(GROUP_TAG) in GROUP_VERSIONS and group.get(GROUP_TAG) != GROUP_VERSION and group.library is None:
            node_group.build_nodes(group)  # in place: its modifiers keep it
            group[GROUP_TAG] = GROUP_VERSION
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
    modifier.node_group = node_group.ensure()
    modifier.show_in_editmode = True
    node_group.hide_geometry_nodes_fields(modifier, SOCKETS)
    helper_of(obj, modifier)
    return modifier


# What Blender names a new Geometry Nodes modifier; a duplicate of an entry (the modifier's menu ▸ Duplicate,
# object.modifier_copy) gets it in 3.4.1 and 4.2.23 (4.5 and later keep the name, "Loop Subdivision.001").
_NODES_DEFAULT_NAME = "GeometryNodes"


def tidy(obj):
    """Every Loop Subdivision modifier of obj named as one, its helper's own fields hidden (node_group): a duplicated
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
            node_group.hide_geometry_nodes_fields(modifier, SOCKETS)
    return renamed


def keep_off_cage(obj):
    """Turns the entries' "Adjust edit cage to modifier result" (On Cage) off again: Blender draws the cage onto a
    modifier's result by the original indices the result carries, which a result made by Python cannot, so the
    cage would not be drawn at all and nothing could be selected. Returns whether one was on."""
    turned = False
    for modifier in obj.modifiers if obj is not None and obj.type == 'MESH' and obj.library is None else ():
        if is_entry(modifier) and modifier.show_on_cage:
            modifier.show_on_cage = False
            turned = True
    return turned


def local_entries():
    """The objects of this file with a live entry, and their entries: a list made before any is changed (drop_base
    removes objects)."""
    return [(obj, modifier) for obj, modifier in ((obj, entry(obj)) for obj in bpy.data.objects)
            if modifier is not None and obj.library is None and obj.users]


def drop_base(obj, modifier):
    """Takes the entry's Base Result away with its helper and mesh. Returns whether it had one."""
    helper = helper_of(obj, modifier, create=False, socket=BASE_SOCKET)
    if helper is None:
        return False
    set_modifier_input(modifier, BASE_SOCKET, None)
    mesh = helper.data
    bpy.data.objects.remove(helper)
    if mesh is not None and mesh.users == 0:
        bpy.data.meshes.remove(mesh)
    return True


def is_first(obj, modifier):
    """Whether the entry comes first among the modifiers that act in the viewport (what Blender's Apply checks)."""
    enabled = [other for other in obj.modifiers if other.show_viewport]
    return not enabled or enabled[0] == modifier


def group_input_identifier(group, name):
    """The key under which a Geometry Nodes modifier keeps the value of the group input called name."""
    if hasattr(group, "interface"):
        return group.interface.items_tree[name].identifier
    return group.inputs[name].identifier


def _modifier_input_values(modifier):
    """Where a Geometry Nodes modifier keeps its inputs' values, and whether that is the RNA struct of releases after
    5.0 (modifier_input)."""
    values = getattr(getattr(modifier, "properties", None), "inputs", None)
    return (values, True) if values is not None else (modifier, False)


def modifier_input(modifier, name):
    """The value a Geometry Nodes modifier gives its node group's input called name (None when unset). Up to 5.0
    the values are ID properties of the modifier, under the socket's identifier (modifier[identifier]); a release
    after 5.0 (5.2.3 has it, 5.0.1 does not) moved them to RNA structs generated per node group,
    modifier.properties.inputs.<identifier>.value, and the modifier itself no longer takes ID properties
    (modifier.get and modifier[identifier] raise "this type doesn't support IDProperties")."""
    values, rna = _modifier_input_values(modifier)
    key = group_input_identifier(modifier.node_group, name)
    if rna:
        socket = getattr(values, key, None)
        return None if socket is None else socket.value
    return values.get(key)


def clear_input(modifier, name):
    """The entry's input called name unset (where it is set: setting it is an update)."""
    if modifier_input(modifier, name) is not None:
        set_modifier_input(modifier, name, None)


def set_modifier_input(modifier, name, value):
    """Sets the value a Geometry Nodes modifier gives its node group's input called name (see modifier_input for
    where each version keeps it)."""
    values, rna = _modifier_input_values(modifier)
    key = group_input_identifier(modifier.node_group, name)
    if rna:
        getattr(values, key).value = value
    else:
        values[key] = value
