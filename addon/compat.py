"""The few places where Blender 3.x and 4.x differ for this add-on, behind one interface.

Blender 4.0 moved edge and vertex creases from dedicated layers (MeshEdge.crease, Mesh.edge_creases,
Mesh.vertex_creases, bmesh's crease layers) to the generic float attributes "crease_edge" and "crease_vert",
made MeshPolygon.loop_total read-only (face sizes follow from loop_start) and moved node group sockets to
NodeTree.interface; 4.1 dropped Auto Smooth, so that custom split normals and marked sharp edges always shade, and
replaced Mesh.calc_normals_split / MeshLoop.normal with Mesh.corner_normals.
"""
import math

import bpy
import numpy as np

USES_CREASE_ATTRIBUTES = bpy.app.version >= (4, 0, 0)
EDGE_CREASE_ATTRIBUTE = "crease_edge"
VERTEX_CREASE_ATTRIBUTE = "crease_vert"


def _read_attribute(mesh, name, domain_size):
    values = np.zeros(domain_size, dtype=np.float32)
    attribute = mesh.attributes.get(name)
    if attribute is not None:
        attribute.data.foreach_get("value", values)
    return values


def _write_attribute(mesh, name, domain, values):
    attribute = mesh.attributes.get(name) or mesh.attributes.new(name, 'FLOAT', domain)
    attribute.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.float32))


def _read_crease_layer(layers, count):
    """Blender 3.x: the first crease layer's values, zeros when there is none."""
    values = np.zeros(count, dtype=np.float32)
    if len(layers):
        layers[0].data.foreach_get("value", values)
    return values


def read_edge_creases(mesh):
    if USES_CREASE_ATTRIBUTES:
        return _read_attribute(mesh, EDGE_CREASE_ATTRIBUTE, len(mesh.edges))
    return _read_crease_layer(mesh.edge_creases, len(mesh.edges))


def write_edge_creases(mesh, values):
    if USES_CREASE_ATTRIBUTES:
        _write_attribute(mesh, EDGE_CREASE_ATTRIBUTE, 'EDGE', values)
    else:
        # Writing MeshEdge.crease creates the crease layer when the mesh has none.
        mesh.edges.foreach_set("crease", np.ascontiguousarray(values, dtype=np.float32))


def has_vertex_creases(mesh):
    if USES_CREASE_ATTRIBUTES:
        return VERTEX_CREASE_ATTRIBUTE in mesh.attributes
    return len(mesh.vertex_creases) > 0


def read_vertex_creases(mesh):
    if USES_CREASE_ATTRIBUTES:
        return _read_attribute(mesh, VERTEX_CREASE_ATTRIBUTE, len(mesh.vertices))
    return _read_crease_layer(mesh.vertex_creases, len(mesh.vertices))


def add_vertex_crease_layer(mesh):
    """Blender 3.x has no Python call that adds the vertex crease layer except through bmesh, which rebuilds the
    mesh: cheap on the empty mesh that apply fills, fine on a cage."""
    if USES_CREASE_ATTRIBUTES:
        if VERTEX_CREASE_ATTRIBUTE not in mesh.attributes:
            mesh.attributes.new(VERTEX_CREASE_ATTRIBUTE, 'FLOAT', 'POINT')
    elif not len(mesh.vertex_creases):
        import bmesh
        bm = bmesh.new()
        try:
            bm.from_mesh(mesh)
            bm.verts.layers.crease.verify()
            bm.to_mesh(mesh)
        finally:
            bm.free()


def write_vertex_creases(mesh, values):
    add_vertex_crease_layer(mesh)
    values = np.ascontiguousarray(values, dtype=np.float32)
    if USES_CREASE_ATTRIBUTES:
        _write_attribute(mesh, VERTEX_CREASE_ATTRIBUTE, 'POINT', values)
    else:
        mesh.vertex_creases[0].data.foreach_set("value", values)


def crease_attribute_names():
    """Attribute names that hold creases (only on 4.x): apply handles them itself, not as generic attributes."""
    return {EDGE_CREASE_ATTRIBUTE, VERTEX_CREASE_ATTRIBUTE} if USES_CREASE_ATTRIBUTES else set()


def set_polygon_loops(mesh, loop_start, loop_total):
    mesh.polygons.foreach_set("loop_start", np.ascontiguousarray(loop_start, dtype=np.int32))
    if not bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly:
        mesh.polygons.foreach_set("loop_total", np.ascontiguousarray(loop_total, dtype=np.int32))


def copy_shading_settings(source, target):
    """What a mesh says about its shading besides per-face flags: Auto Smooth up to 4.0 (4.1 dropped it for a
    modifier), and its custom properties."""
    if hasattr(source, "use_auto_smooth"):
        target.use_auto_smooth = source.use_auto_smooth
        target.auto_smooth_angle = source.auto_smooth_angle
    for key in source.keys():
        value = source[key]
        target[key] = value.original if isinstance(value, bpy.types.ID) else value


def add_modifier_button(draw):
    """Puts draw(self, context) under Properties ▸ Modifiers ▸ Add Modifier: 3.x draws that button in the panel
    DATA_PT_modifiers, 4.0+ has a menu with a Generate section. Returns what remove_modifier_button needs."""
    menu = getattr(bpy.types, "OBJECT_MT_modifier_add_generate", None)
    target = menu if menu is not None else bpy.types.DATA_PT_modifiers
    target.append(draw)
    return target


def remove_modifier_button(target, draw):
    target.remove(draw)


# Blender draws each modifier in an instanced panel of this type; a Python sub-panel of it is drawn inside every
# Geometry Nodes modifier's panel, with that modifier as the panel's custom_data.
NODES_MODIFIER_PANEL = "MOD_PT_GeometryNodes"


def add_group_socket(group, in_out, socket_type, name):
    """A node group input or output ('INPUT'/'OUTPUT'): NodeTree.interface from 4.0, inputs/outputs before."""
    if hasattr(group, "interface"):
        return group.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    return (group.inputs if in_out == 'INPUT' else group.outputs).new(socket_type, name)


def group_input_identifier(group, name):
    """The key under which a Geometry Nodes modifier keeps the value of the group input called name."""
    if hasattr(group, "interface"):
        return group.interface.items_tree[name].identifier
    return group.inputs[name].identifier


def bmesh_crease_layers(bm):
    """The bmesh layers of edge and vertex creases, made when missing: (edge layer, vertex layer)."""
    if USES_CREASE_ATTRIBUTES:
        edges = bm.edges.layers.float.get(EDGE_CREASE_ATTRIBUTE)
        verts = bm.verts.layers.float.get(VERTEX_CREASE_ATTRIBUTE)
        return (edges if edges is not None else bm.edges.layers.float.new(EDGE_CREASE_ATTRIBUTE),
                verts if verts is not None else bm.verts.layers.float.new(VERTEX_CREASE_ATTRIBUTE))
    return bm.edges.layers.crease.verify(), bm.verts.layers.crease.verify()


def smooth_by_angle(mesh, angle):
    """Smooth shading, split where faces meet at more than angle (radians): Auto Smooth up to 4.0, sharp edges set
    from the angle from 4.1 on."""
    if hasattr(mesh, "use_auto_smooth"):
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = angle
    else:
        mesh.set_sharp_from_angle(angle=angle)


def shades_sharp_edges(mesh):
    """Whether custom split normals and marked sharp edges show in the mesh's shading: with Auto Smooth up to 4.0,
    always from 4.1."""
    return getattr(mesh, "use_auto_smooth", True)


def shade_sharp_edges(mesh):
    """Makes marked sharp edges (and custom split normals) shade: up to 4.0 they do only with Auto Smooth, which this
    turns on; a mesh that had it off gets the widest angle, so that only the marks split the shading. From 4.1 they
    always do."""
    if hasattr(mesh, "use_auto_smooth") and not mesh.use_auto_smooth:
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.pi


def custom_normals_in_use(mesh):
    return mesh.has_custom_normals and shades_sharp_edges(mesh)


def read_corner_normals(mesh):
    """The normal Blender shades each corner (loop) with, custom split normals included: (L, 3) float32."""
    values = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    if hasattr(mesh, "corner_normals"):
        mesh.corner_normals.foreach_get("vector", values)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", values)
        mesh.free_normals_split()
    return values.reshape(-1, 3)


def set_custom_normals(mesh, normals, vertex_normals=None):
    """Custom split normals, one per loop ((L, 3); a zero vector keeps Blender's own normal at that corner), or, when
    every corner of a vertex has the same one, vertex_normals (V, 3), which Blender takes several times faster. Up to
    4.0 they show only with Auto Smooth, which this turns on; a mesh that had it off gets the widest angle, so that
    only marked sharp edges (and the normals themselves) split the shading. Blender marks the edges sharp where the
    normals of one smooth fan differ (across creases)."""
    shade_sharp_edges(mesh)
    if vertex_normals is not None:
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(vertex_normals, dtype=np.float32))
    else:
        mesh.normals_split_custom_set(np.ascontiguousarray(normals, dtype=np.float32).reshape(-1, 3))


def shading_state(mesh):
    """What set_custom_normals may change besides the normals: Auto Smooth and its angle up to 4.0; None from 4.1."""
    return (mesh.use_auto_smooth, mesh.auto_smooth_angle) if hasattr(mesh, "use_auto_smooth") else None


def restore_shading_state(mesh, state):
    if state is not None:
        mesh.use_auto_smooth, mesh.auto_smooth_angle = state


def clear_custom_normals(mesh, holder):
    """Removes the custom split normals of mesh, the data of the object holder (Blender's operator is the only way
    in every version; it needs the object, not the mesh, and works on one linked to no scene)."""
    if mesh.has_custom_normals:
        with bpy.context.temp_override(object=holder, active_object=holder):
            bpy.ops.mesh.customdata_custom_splitnormals_clear()
