"""The few places where Blender 3.x and 4.x differ for this add-on, behind one interface.

Blender 4.0 moved edge and vertex creases from dedicated layers (MeshEdge.crease, Mesh.edge_creases,
Mesh.vertex_creases, bmesh's crease layers) to the generic float attributes "crease_edge" and "crease_vert",
made MeshPolygon.loop_total read-only (face sizes follow from loop_start) and renamed the built-in GPU shaders.
"""
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


def builtin_shader_name(kind):
    """kind 'UNIFORM_COLOR' or 'SMOOTH_COLOR': Blender 4.0 dropped the '3D_' prefix."""
    return kind if bpy.app.version >= (4, 0, 0) else "3D_" + kind
