"""Edge and vertex creases, where each version keeps them: Blender 4.0 moved them from dedicated layers
(MeshEdge.crease, Mesh.edge_creases, Mesh.vertex_creases, bmesh's crease layers) to the generic float attributes
"crease_edge" and "crease_vert".
"""
import bpy
import numpy as np

from .mesh_arrays import write_named_attribute

USES_CREASE_ATTRIBUTES = bpy.app.version >= (4, 0, 0)


EDGE_CREASE_ATTRIBUTE = "crease_edge"


VERTEX_CREASE_ATTRIBUTE = "crease_vert"


def _read_creases(mesh, attribute, layers, count):
    """The values of the crease attribute (4.0 on) or of the first of the mesh's crease layers of that name (3.x),
    zeros where the mesh has none."""
    values = np.zeros(count, dtype=np.float32)
    if USES_CREASE_ATTRIBUTES:
        source = mesh.attributes.get(attribute)
    else:
        source = next(iter(getattr(mesh, layers)), None)
    if source is not None:
        source.data.foreach_get("value", values)
    return values


def read_edge_creases(mesh):
    return _read_creases(mesh, EDGE_CREASE_ATTRIBUTE, "edge_creases", len(mesh.edges))


def write_edge_creases(mesh, values):
    if USES_CREASE_ATTRIBUTES:
        write_named_attribute(mesh, EDGE_CREASE_ATTRIBUTE, 'EDGE', values)
    else:
        # Writing MeshEdge.crease creates the crease layer when the mesh has none.
        mesh.edges.foreach_set("crease", np.ascontiguousarray(values, dtype=np.float32))


def has_vertex_creases(mesh):
    if USES_CREASE_ATTRIBUTES:
        return VERTEX_CREASE_ATTRIBUTE in mesh.attributes
    return len(mesh.vertex_creases) > 0


def read_vertex_creases(mesh):
    return _read_creases(mesh, VERTEX_CREASE_ATTRIBUTE, "vertex_creases", len(mesh.vertices))


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
        write_named_attribute(mesh, VERTEX_CREASE_ATTRIBUTE, 'POINT', values)
    else:
        mesh.vertex_creases[0].data.foreach_set("value", values)


def crease_attribute_names():
    """Attribute names that hold creases (only on 4.x): apply handles them itself, not as generic attributes."""
    return {EDGE_CREASE_ATTRIBUTE, VERTEX_CREASE_ATTRIBUTE} if USES_CREASE_ATTRIBUTES else set()


def bmesh_crease_layers(bm):
    """The bmesh layers of edge and vertex creases, made when missing: (edge layer, vertex layer)."""
    if USES_CREASE_ATTRIBUTES:
        edges = bm.edges.layers.float.get(EDGE_CREASE_ATTRIBUTE)
        verts = bm.verts.layers.float.get(VERTEX_CREASE_ATTRIBUTE)
        return (edges if edges is not None else bm.edges.layers.float.new(EDGE_CREASE_ATTRIBUTE),
                verts if verts is not None else bm.verts.layers.float.new(VERTEX_CREASE_ATTRIBUTE))
    return bm.edges.layers.crease.verify(), bm.verts.layers.crease.verify()
