"""The node group every Loop Subdivision entry runs, and its sockets, as each version builds them: node group
sockets moved to NodeTree.interface in 4.0, which also lets a socket's field be hidden from the modifier's panel; 4.3
added the Warning node; 3.4's Switch and Compare carry one socket per data type under the same name.

The group shows the Result helper's mesh (Object Info, original space); the Base Result's where the input is the mesh
it was made from; the input where there is no result (a Blender without the add-on). See stack.py for the entries and
helpers that use it.
"""
import bpy

ENTRY_NAME = "Loop Subdivision"
GROUP_TAG = "loop_subdivision"  # on the node group: the version of its layout
GROUP_VERSION = 3
# 1: the helper's mesh alone (files saved before 2026-11-26); 2: no Base Result (before 2026-12-07).
GROUP_VERSIONS = (1, 2, GROUP_VERSION)
RESULT_SOCKET = "Result"
# The subdivision of the object's own mesh, where the entry is not first (live.py): what Blender's own Apply of the
# entry gives, since it evaluates the modifier on that mesh alone while the modifiers above stay, as Subdivision
# Surface's Apply does. Its mesh keeps the positions it was made from in this point attribute (first points), by
# which the node group knows that mesh when it is the input.
BASE_SOCKET = "Base Result"
BASE_INPUT_ATTRIBUTE = "loop_subdivision_input"
SOCKETS = (RESULT_SOCKET, BASE_SOCKET)


def ensure():
    """The shared node group of every entry, made when the file has none."""
    group = next((group for group in bpy.data.node_groups if group.get(GROUP_TAG) == GROUP_VERSION), None)
    if group is None:
        group = bpy.data.node_groups.new(ENTRY_NAME, 'GeometryNodeTree')
        # Blender expects a geometry input first: the cage, shown when there is no result.
        add_group_socket(group, 'INPUT', 'NodeSocketGeometry', "Geometry")
        add_group_socket(group, 'OUTPUT', 'NodeSocketGeometry', "Geometry")
        build_nodes(group)
        group[GROUP_TAG] = GROUP_VERSION
    return group


def build_nodes(group):
    """The group's inputs (those it lacks) and nodes: the Result helper's mesh (Object Info, original space: the
    helper's coordinates are the owner's), except

    - where the input is the mesh the Base Result was made from (as many points, at the very positions it keeps): the
      Base Result, without the attribute that keeps them. That is Blender's own Apply of an entry that is not first,
      which evaluates the modifier on the object's own mesh alone while the modifiers above stay: the Result, made
      from their output, would be baked into the mesh under them (a Mirror above: every face twice);
    - where the Result helper has no mesh (no helper, or an empty one: a file saved without its result and opened
      where the add-on is missing), the input, so that the object shows its cage, never nothing; from 4.3 a warning
      in the modifier's panel says why (add_warning)."""
    for name in SOCKETS:
        if not has_group_input(group, name):
            add_group_socket(group, 'INPUT', 'NodeSocketObject', name)
    group.nodes.clear()
    nodes, links = group.nodes, group.links
    group_input = nodes.new('NodeGroupInput')

    def object_info(socket):
        info = nodes.new('GeometryNodeObjectInfo')
        info.transform_space = 'ORIGINAL'
        links.new(group_input.outputs[socket], info.inputs["Object"])
        return info

    def feed(sockets, values):
        """Links each of the sockets to its value's socket, or sets it to the value."""
        for socket, value in zip(sockets, values):
            if isinstance(value, bpy.types.NodeSocket):
                links.new(value, socket)
            else:
                socket.default_value = value

    def connect(node, names, values):
        """Feeds node's inputs of these names (those its current data type shows) with values."""
        feed(enabled_sockets(node.inputs, *names), values)

    def domain_size(geometry):
        size = nodes.new('GeometryNodeAttributeDomainSize')
        size.component = 'MESH'
        links.new(geometry, size.inputs["Geometry"])
        return size

    def math(operation, *values):
        """A Math node (1 for true, 0 for false where it compares): of the comparing nodes the one a file keeps
        smallest (3 sockets to the Compare node's 13)."""
        node = nodes.new('ShaderNodeMath')
        node.operation = operation
        feed(node.inputs, values)
        return node.outputs["Value"]

    def switch(condition, false, true):
        node = nodes.new('GeometryNodeSwitch')
        node.input_type = 'GEOMETRY'
        connect(node, ("Switch", "False", "True"), (condition, false, true))
        return enabled_sockets(node.outputs, "Output")[0]

    info, base = object_info(RESULT_SOCKET), object_info(BASE_SOCKET)
    result_points = domain_size(info.outputs["Geometry"]).outputs["Point Count"]
    missing = add_warning(group, math('LESS_THAN', result_points, 0.5),
                                 "The Loop Subdivision add-on is not enabled: the cage is shown")
    shown = switch(missing, info.outputs["Geometry"], group_input.outputs["Geometry"])

    # The input is the Base Result's mesh: as many points and faces as it was made from (the Base helper's location,
    # see show_base), each point where the Base Result keeps it.
    separate = nodes.new('ShaderNodeSeparateXYZ')
    links.new(base.outputs["Location"], separate.inputs[0])
    size = domain_size(group_input.outputs["Geometry"])
    same_count = math('MULTIPLY', math('COMPARE', size.outputs["Point Count"], separate.outputs["X"], 0.5),
                      math('COMPARE', size.outputs["Face Count"], separate.outputs["Y"], 0.5))
    kept = nodes.new('GeometryNodeInputNamedAttribute')
    kept.data_type = 'FLOAT_VECTOR'
    connect(kept, ("Name",), (BASE_INPUT_ATTRIBUTE,))
    sample = nodes.new('GeometryNodeSampleIndex')
    sample.data_type, sample.domain = 'FLOAT_VECTOR', 'POINT'
    connect(sample, ("Geometry", "Value", "Index"), (base.outputs["Geometry"],
                                                    enabled_sockets(kept.outputs, "Attribute")[0],
                                                    nodes.new('GeometryNodeInputIndex').outputs["Index"]))
    distance = nodes.new('ShaderNodeVectorMath')
    distance.operation = 'DISTANCE'
    links.new(nodes.new('GeometryNodeInputPosition').outputs["Position"], distance.inputs[0])
    links.new(enabled_sockets(sample.outputs, "Value")[0], distance.inputs[1])
    farthest = nodes.new('GeometryNodeAttributeStatistic')
    farthest.data_type, farthest.domain = 'FLOAT', 'POINT'
    connect(farthest, ("Geometry", "Attribute"), (group_input.outputs["Geometry"], distance.outputs["Value"]))
    same_positions = math('COMPARE', farthest.outputs["Max"], 0.0, 0.0)  # exactly
    both = math('MULTIPLY', same_count, same_positions)
    unmarked = nodes.new('GeometryNodeRemoveAttribute')
    links.new(base.outputs["Geometry"], unmarked.inputs["Geometry"])
    unmarked.inputs["Name"].default_value = BASE_INPUT_ATTRIBUTE
    group_output = nodes.new('NodeGroupOutput')
    links.new(switch(both, shown, unmarked.outputs["Geometry"]), group_output.inputs["Geometry"])
    for column, node in enumerate(nodes):
        node.location = (250 * (column % 6), -200 * (column // 6))


def hide_geometry_nodes_fields(modifier, sockets):
    """Hides what the panel of a Geometry Nodes modifier draws above the Loop Subdivision settings, as far as the
    version lets Python: returns the names of what stays shown.

    3.4 (3.4.1 here) offers nothing: the modifier panel always draws the node-group picker (with its user count,
    fake-user, copy and unlink buttons) and every group input's field ("Result", "Base Result"); "Output Attributes"
    and "Internal Dependencies" are sub-panels of it registered in C, with no flag or poll a Python add-on can change.
    4.2 and 4.5 (4.2.23 and 4.5.15 here; 4.0 and 4.1 are not installed): NodesModifier.show_group_selector hides the
    picker, and the group inputs' interface socket flag hide_in_modifier hides their fields (the modifier keeps their
    values, and runs with them). "Output Attributes" is drawn only for group outputs that take an attribute name
    (the group has one, a Geometry); the "Manage" panel (Bake, Named Attributes: the former "Internal Dependencies")
    stays, closed by default, with no flag to hide it.
    5.0 on (5.0.1 and 5.2.3 here): as 4.5, and NodesModifier.show_manage_panel hides "Manage" too.

    A duplicate of the modifier (modifier_copy) copies these flags; the socket flag is the shared group's."""
    shown = []
    if hasattr(modifier, "show_group_selector"):
        if modifier.show_group_selector:
            modifier.show_group_selector = False
    else:
        shown.append("node group")
    group = modifier.node_group
    for name in sockets:
        socket = group.interface.items_tree.get(name) if hasattr(group, "interface") else None
        if socket is not None and hasattr(socket, "hide_in_modifier"):
            if not socket.hide_in_modifier:
                socket.hide_in_modifier = True
        else:
            shown.append(name)
    if not hasattr(group, "interface"):
        shown.append("Output Attributes")
    if hasattr(modifier, "show_manage_panel"):
        if modifier.show_manage_panel:
            modifier.show_manage_panel = False
    else:
        shown.append("Internal Dependencies" if not hasattr(group, "interface") else "Manage")
    return shown


HAS_WARNING_NODE = hasattr(bpy.types, "GeometryNodeWarning")


def show_result_field(show):
    """Shows (or hides again) the Result field in the entries' panel, where the version hides it
    (hide_geometry_nodes_fields) and has no Warning node to say that the add-on is missing (4.0 to 4.2): in a file saved
    without results, the field names the placeholder object, "Add-on off"."""
    group = ensure()
    socket = group.interface.items_tree.get(RESULT_SOCKET) if hasattr(group, "interface") else None
    if socket is not None and hasattr(socket, "hide_in_modifier") and not HAS_WARNING_NODE:
        socket.hide_in_modifier = not show


def add_group_socket(group, in_out, socket_type, name):
    """A node group input or output ('INPUT'/'OUTPUT'): NodeTree.interface from 4.0, inputs/outputs before."""
    if hasattr(group, "interface"):
        return group.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    return (group.inputs if in_out == 'INPUT' else group.outputs).new(socket_type, name)


def enabled_sockets(sockets, *names):
    """The sockets of a node with these names, among those its current type shows: 3.4's Switch and Compare carry
    one socket per data type under the same name (identifiers "False_006" and the like), 4.1+'s Switch one."""
    return [next(socket for socket in sockets if socket.enabled and socket.name == name) for name in names]


def add_warning(group, condition, message):
    """A Warning node (4.3+; 4.5.15 here) on condition, which the modifier's panel shows while it holds; returns the
    socket to use in place of condition, through which the node is evaluated. Earlier versions have no such node:
    condition itself."""
    if not HAS_WARNING_NODE:
        return condition
    warning = group.nodes.new('GeometryNodeWarning')
    warning.warning_type = 'WARNING'
    group.links.new(condition, warning.inputs["Show"])
    warning.inputs["Message"].default_value = message
    return warning.outputs["Show"]


def has_group_input(group, name):
    if hasattr(group, "interface"):
        item = group.interface.items_tree.get(name)
        return item is not None and item.item_type == 'SOCKET' and item.in_out == 'INPUT'
    return name in group.inputs
