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

from . import compat

ENTRY_NAME = "Loop Subdivision"
GROUP_TAG = "loop_subdivision"  # on the node group: the version of its layout
GROUP_VERSION = 2
GROUP_VERSIONS = (1, GROUP_VERSION)  # 1: the helper's mesh alone (files saved before 2026-11-26)
OWNER_TAG = "loop_subdivision_owner"  # on a helper: the name of the object whose entry it serves
RESULT_TAG = "loop_subdivision_result"  # on a helper's mesh (and the meshes that replaced it): made by the add-on
RESULT_SOCKET = "Result"
# A file saved without its results (the default; Object.loop_subdivision.store_result keeps them) points every entry
# at one empty object of this name: where the add-on is missing the entry shows the cage, and its panel shows this
# name in the Result field (3.4, 4.2; 4.3+ show a warning from the node group).
PLACEHOLDER_NAME = "Enable the Loop Subdivision add-on"
PLACEHOLDER_TAG = "loop_subdivision_placeholder"


def node_group():
    """The shared node group of every entry, made when the file has none."""
    group = next((group for group in bpy.data.node_groups if group.get(GROUP_TAG) == GROUP_VERSION), None)
    if group is None:
        group = bpy.data.node_groups.new(ENTRY_NAME, 'GeometryNodeTree')
        # Blender expects a geometry input first: the cage, shown when there is no result.
        compat.add_group_socket(group, 'INPUT', 'NodeSocketGeometry', "Geometry")
        compat.add_group_socket(group, 'INPUT', 'NodeSocketObject', RESULT_SOCKET)
        compat.add_group_socket(group, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
        _build_nodes(group)
        group[GROUP_TAG] = GROUP_VERSION
    return group


def _build_nodes(group):
    """The group's nodes: the helper's mesh (Object Info, original space: the helper's coordinates are the owner's),
    except

    - where the helper has no mesh (no helper, or an empty one: a file saved without its result and opened where the
      add-on is missing), the input, so that the object shows its cage, never nothing; from 4.3 a warning in the
      modifier's panel says why (compat.add_warning);
    - where the input has not the number of vertices the result was made from (the helper's location x, see
      set_input_guard; 0: no check), nothing, or the input where Blender would apply nothing
      (compat.STALE_RESULT_OUTPUT): that is Blender's own Apply of an entry that is not first, which evaluates the
      modifier on the object's mesh alone while the modifiers above stay; the result, made from their output, would
      be baked into the mesh under them (a Mirror above: every face twice)."""
    group.nodes.clear()
    nodes, links = group.nodes, group.links
    group_input = nodes.new('NodeGroupInput')
    info = nodes.new('GeometryNodeObjectInfo')
    info.transform_space = 'ORIGINAL'
    links.new(group_input.outputs[RESULT_SOCKET], info.inputs["Object"])

    def point_count(geometry):
        size = nodes.new('GeometryNodeAttributeDomainSize')
        size.component = 'MESH'
        links.new(geometry, size.inputs["Geometry"])
        return size.outputs["Point Count"]

    def compare(operation, a, b):
        node = nodes.new('FunctionNodeCompare')
        node.data_type, node.operation = 'FLOAT', operation
        for socket, value in zip(compat.enabled_sockets(node.inputs, "A", "B"), (a, b)):
            if isinstance(value, bpy.types.NodeSocket):
                links.new(value, socket)
            else:
                socket.default_value = value
        return node.outputs["Result"]

    def switch(condition, false, true):
        node = nodes.new('GeometryNodeSwitch')
        node.input_type = 'GEOMETRY'
        inputs = compat.enabled_sockets(node.inputs, "Switch", "False", "True")
        for socket, value in zip(inputs, (condition, false, true)):
            if value is not None:
                links.new(value, socket)
        return compat.enabled_sockets(node.outputs, "Output")[0]

    missing = compat.add_warning(group, compare('LESS_THAN', point_count(info.outputs["Geometry"]), 0.5),
                                 "The Loop Subdivision add-on is not enabled: the cage is shown")
    shown = switch(missing, info.outputs["Geometry"], group_input.outputs["Geometry"])
    separate = nodes.new('ShaderNodeSeparateXYZ')
    links.new(info.outputs["Location"], separate.inputs[0])
    guarded = compare('GREATER_THAN', separate.outputs["X"], 0.5)
    other_input = compare('NOT_EQUAL', point_count(group_input.outputs["Geometry"]), separate.outputs["X"])
    both = nodes.new('FunctionNodeBooleanMath')
    both.operation = 'AND'
    links.new(guarded, both.inputs[0])
    links.new(other_input, both.inputs[1])
    stale = group_input.outputs["Geometry"] if compat.STALE_RESULT_OUTPUT == 'INPUT' else None
    group_output = nodes.new('NodeGroupOutput')
    links.new(switch(both.outputs[0], shown, stale), group_output.inputs["Geometry"])
    for column, node in enumerate(nodes):
        node.location = (250 * (column % 6), -200 * (column // 6))


def set_input_guard(helper, input_points):
    """What the node group checks its input against (_build_nodes): the number of vertices of the input the
    helper's result was made from, or 0 for no check (what a new helper has). Kept in the helper's location, which
    nothing else reads (Object Info in original space does not move the geometry by it); exact up to 2^24."""
    if helper.location.x != input_points:
        helper.location.x = input_points


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


def _serves(helper, obj):
    """Whether helper is (or may become) the helper of obj's entry: it names obj, or it names no object whose entry
    uses it (its owner was renamed, or deleted and a linked duplicate remains)."""
    name = owner_name(helper)
    if name == obj.name:
        return True
    owner = bpy.data.objects.get(name) if isinstance(name, str) else None
    owner_entry = entry(owner) if owner is not None and owner != obj and owner.users else None
    return owner_entry is None or compat.modifier_input(owner_entry, RESULT_SOCKET) != helper


def helper_of(obj, modifier, create=True):
    """The object that carries this entry's result; the object's unused helper, or a new one, when the entry has none
    of its own (None with create=False)."""
    current = compat.modifier_input(modifier, RESULT_SOCKET)
    if current is not None and is_helper(current) and _serves(current, obj):
        if current.get(OWNER_TAG) != obj.name and current.library is None:
            current[OWNER_TAG] = obj.name
        return current
    if not create:
        return None
    helper = next((other for other in bpy.data.objects
                    if is_helper(other) and other.library is None and owner_name(other) == obj.name
                    and not other.users), None)
    if helper is None:
        mesh = bpy.data.meshes.new(f"{obj.name} ({ENTRY_NAME})")
        mesh[RESULT_TAG] = True
        helper = bpy.data.objects.new(mesh.name, mesh)
    helper[OWNER_TAG] = obj.name
    compat.set_modifier_input(modifier, RESULT_SOCKET, helper)
    return helper


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
                helper = compat.modifier_input(modifier, RESULT_SOCKET)
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
            _build_nodes(group)  # in place: its modifiers keep it
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
    modifier.node_group = node_group()
    modifier.show_in_editmode = True
    compat.hide_geometry_nodes_fields(modifier, RESULT_SOCKET)
    helper_of(obj, modifier)
    return modifier


# What Blender names a new Geometry Nodes modifier; a duplicate of an entry (the modifier's menu ▸ Duplicate,
# object.modifier_copy) gets it in 3.4.1 and 4.2.23 (4.5 and later keep the name, "Loop Subdivision.001").
_NODES_DEFAULT_NAME = "GeometryNodes"


def tidy(obj):
    """Every Loop Subdivision modifier of obj named as one, its helper's own fields hidden (compat): a duplicated
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
            compat.hide_geometry_nodes_fields(modifier, RESULT_SOCKET)
    return renamed


def is_first(obj, modifier):
    """Whether the entry comes first among the modifiers that act in the viewport (what Blender's Apply checks)."""
    enabled = [other for other in obj.modifiers if other.show_viewport]
    return not enabled or enabled[0] == modifier
