"""Moving mesh arrays between Blender and numpy: the mesh's own arrays (positions, edges, corners, faces, marks), its
attributes and UV maps, each the fastest way the version offers and through Blender's accessors where it offers none
(views of Blender's memory: memory_views).

From 4.0 Blender keeps a mesh's arrays as generic attributes ("position", ".edge_verts", ".corner_vert",
".corner_edge", "sharp_face", "material_index", the edge marks), whose foreach_get and foreach_set copy a block, where
the legacy collections (MeshVertex.co, MeshEdge.vertices, MeshLoop.vertex_index, ...) go element by element; 4.0 also
made MeshPolygon.loop_total read-only (face sizes follow from loop_start).
"""
import ctypes

import bpy
import numpy as np

from ..model import geometry
from . import memory_views

CREASE_TAG = "loop_crease"


VERTEX_TYPE_TAG = "loop_vertex_type"


def read_array(collection, prop, count, width, dtype):
    values = np.empty(count * width, dtype=dtype)
    collection.foreach_get(prop, values)
    return values.reshape(count, width) if width > 1 else values


def read_attribute(attribute, count):
    prop, width, dtype = geometry.ATTRIBUTE_LAYOUT[attribute.data_type]
    return read_array(attribute.data, prop, count, width, dtype).reshape(count, width)


def fill_attribute(attribute, data_type, values):
    attribute.data.foreach_set(geometry.ATTRIBUTE_LAYOUT[data_type][0], np.ascontiguousarray(values).ravel())


def add_attribute(mesh, name, domain, data_type, values):
    attribute = mesh.attributes.new(name, data_type, domain)
    fill_attribute(attribute, data_type, values)
    return attribute


def read_named_attribute(mesh, name, domain_size, dtype=np.float32):
    """The generic attribute `name`'s values, zero (False) where the mesh has none."""
    values = np.zeros(domain_size, dtype=dtype)
    attribute = mesh.attributes.get(name)
    if attribute is not None:
        attribute.data.foreach_get("value", values)
    return values


def write_named_attribute(mesh, name, domain, values):
    attribute = mesh.attributes.get(name) or mesh.attributes.new(name, 'FLOAT', domain)
    attribute.data.foreach_set("value", np.ascontiguousarray(values, dtype=np.float32))


# Blender 4.5 (4.5.15 here; 4.2.23 has neither, 4.3 and 4.4 are not installed: upstream made both changes for 5.0
# and 4.5 took them over) keeps UV seams as the visible edge attribute "uv_seam" (".uv_seam", hidden, before) and
# custom normals as the attribute "custom_normal": a corner int16 pair in tangent space (what
# normals_split_custom_set writes), or "free" normals, a float vector on the point, face or corner domain (e.g. from a
# Set Mesh Normal node, or written directly), which Blender shades with as they are.
NAMES_SEAMS_AND_NORMALS = bpy.app.version >= (4, 5, 0)


SEAM_ATTRIBUTE = "uv_seam"


CUSTOM_NORMAL_ATTRIBUTE = "custom_normal"


def seam_and_normal_attribute_names():
    """Attribute names under which 4.5+ keeps UV seams and custom normals (empty before 4.5), which apply handles
    itself (MeshEdge.use_seam, the corner normals): carried over as generic attributes too, "uv_seam" came out twice
    ("uv_seam.001"), and a free "custom_normal" was refined as a plain vector and never normalised (and, on the point
    domain, with the vertex rules instead of per face), because normals_split_custom_set leaves a mesh that has free
    normals as it is (seen in 4.5.15, 5.0.1 and 5.2.3)."""
    return {SEAM_ATTRIBUTE, CUSTOM_NORMAL_ATTRIBUTE} if NAMES_SEAMS_AND_NORMALS else set()


# Where the mesh's own arrays are generic attributes (4.2.23 and later here: "position", ".edge_verts",
# ".corner_vert", ".corner_edge"; 3.4.1 has MVert, MEdge and MLoop), foreach_set on the attribute copies the array in
# one block: 25-100 times faster than the legacy collections (MeshVertex.co, MeshEdge.vertices, MeshLoop.vertex_index
# and edge_index), which go element by element (docs/benchmark.md, Apply). The attributes are looked up by name: a
# name beginning with "." is Blender's own, and 3.4 keeps no generic layer named "position".
def _write_array(mesh, name, prop, legacy, legacy_prop, values):
    """values into the attribute `name` (its `prop`) where the mesh keeps one, else into the legacy collection's
    legacy_prop (its structs' field in place where it can: memory_views.struct_field)."""
    attribute = mesh.attributes.get(name)
    if attribute is None:
        _write_legacy(legacy, legacy_prop, values)
    elif not memory_views.holds(attribute, values):
        attribute.data.foreach_set(prop, values)


def _write_legacy(collection, prop, values):
    """values into a legacy collection's prop: into its structs' field where memory_views.struct_field views it, else
    through foreach_set."""
    field = memory_views.struct_field(collection, prop)
    if field is None:
        collection.foreach_set(prop, values)
    else:
        field[...] = values.reshape(field.shape)


def write_positions(mesh, positions):
    """The vertices' positions, (V, 3): nothing to do where they are the mesh's own array (position_array)."""
    values = np.ascontiguousarray(positions, dtype=np.float32).ravel()
    _write_array(mesh, "position", "vector", mesh.vertices, "co", values)


def write_edges(mesh, edge_vertices, corner_edges, corner_vertices):
    """The edges' vertex pairs, (E, 2), and each face corner's (loop's) edge and vertex, (L,) each."""
    _write_array(mesh, ".edge_verts", "value", mesh.edges, "vertices",
                 np.ascontiguousarray(edge_vertices, dtype=np.int32).ravel())
    _write_array(mesh, ".corner_edge", "value", mesh.loops, "edge_index",
                 np.ascontiguousarray(corner_edges, dtype=np.int32).ravel())
    _write_array(mesh, ".corner_vert", "value", mesh.loops, "vertex_index",
                 np.ascontiguousarray(corner_vertices, dtype=np.int32).ravel())


def edge_arrays(mesh):
    """Blender's own arrays of a mesh's edges' vertex pairs, of its corners' edges and of its corners' vertices, as
    writable (E, 2), (L,) and (L,) int32 views of its memory, for the core to write in place (write_edges' values
    without a copy), or None. From 4.0 they are the attributes .edge_verts, .corner_edge and .corner_vert, whose items
    point at their elements; a new mesh's arrays, just added, are its own (no other mesh shares them). New numpy
    arrays of their size cost page faults of their own inside Blender, which reuses little of its freed memory, on top
    of the mesh's (docs/benchmark.md)."""
    edge_block = _attribute_view(mesh, ".edge_verts", len(mesh.edges), 2)
    corner_edge_block = _attribute_view(mesh, ".corner_edge", len(mesh.loops), 1)
    corner_vertex_block = _attribute_view(mesh, ".corner_vert", len(mesh.loops), 1)
    if edge_block is None or corner_edge_block is None or corner_vertex_block is None:
        return None
    return edge_block, corner_edge_block.reshape(-1), corner_vertex_block.reshape(-1)


def position_array(mesh):
    """Blender's own array of a new mesh's vertex positions, as a writable (V, 3) float32 view of its memory for the
    core to evaluate into (as edge_arrays), or None: 3.4 keeps positions in MVert structs among other fields."""
    return _attribute_view(mesh, "position", len(mesh.vertices), 3, ctypes.c_float)


def write_uvs(mesh, name, uvs):
    """A UV map's values per corner, (L, 2): through its FLOAT2 corner attribute where the version keeps UV maps as
    attributes (4.2.23 and later here; 3.4.1 has MLoopUV layers, which mesh.attributes does not list), 15-25 times
    faster than MeshUVLoop.uv."""
    values = np.ascontiguousarray(uvs, dtype=np.float32).ravel()
    attribute = mesh.attributes.get(name)
    if attribute is not None and (attribute.data_type, attribute.domain) == ('FLOAT2', 'CORNER'):
        attribute.data.foreach_set("vector", values)
    else:
        mesh.uv_layers[name].data.foreach_set("uv", values)


def write_smooth(mesh, smooth):
    """Each face's smooth shading, (F,) bool, or None where every face is smooth, on a new mesh. From 4.0 Blender keeps
    it as the `sharp_face` attribute, absent while every face is smooth (as a new mesh's are): one block copy, where
    MeshPolygon.use_smooth takes 43 ms per million faces in 4.5. 3.4 keeps it in the faces themselves, flat when
    new."""
    if bpy.app.version < (4, 0, 0):
        smooth = np.ones(len(mesh.polygons), dtype=bool) if smooth is None else smooth
        mesh.polygons.foreach_set("use_smooth", np.ascontiguousarray(smooth, dtype=bool))
    elif smooth is not None and not smooth.all():
        mesh.attributes.new("sharp_face", 'BOOLEAN', 'FACE').data.foreach_set("value", ~smooth)


# Reading the cage the same way (4.0 and later: face offsets are offsets, so the faces' corners follow one another):
# foreach_get on the attribute copies the array in one block, where the legacy collections go element by element,
# 0.01 ms against 1-8 ms each for a 40,000-quad grid's vertices, corners and edges in 4.5 (docs/benchmark.md). Every
# live update reads the cage anew.
READS_ATTRIBUTES = bpy.app.version >= (4, 0, 0)


def _read_array(mesh, name, prop, legacy, legacy_prop, count, width, dtype):
    """The attribute `name` (its `prop`) where the mesh keeps one, else the legacy collection's legacy_prop."""
    attribute = mesh.attributes.get(name) if READS_ATTRIBUTES else None
    if attribute is not None:
        return read_array(attribute.data, prop, count, width, dtype)
    field = memory_views.struct_field(legacy, legacy_prop) if dtype == np.int32 else None
    if field is not None:
        values = np.ascontiguousarray(field)
        return values if width > 1 else values.reshape(-1)
    return read_array(legacy, legacy_prop, count, width, dtype)


def read_positions(mesh):
    """The vertices' positions, (V, 3) float32."""
    return _read_array(mesh, "position", "vector", mesh.vertices, "co", len(mesh.vertices), 3, np.float32)


def read_edge_vertices(mesh):
    """The edges' vertex pairs, (E, 2) int32."""
    return _read_array(mesh, ".edge_verts", "value", mesh.edges, "vertices", len(mesh.edges), 2, np.int32)


def read_corners(mesh):
    """Each face corner's (loop's) vertex and edge, (L,) int32 each."""
    count = len(mesh.loops)
    return (_read_array(mesh, ".corner_vert", "value", mesh.loops, "vertex_index", count, 1, np.int32),
            _read_array(mesh, ".corner_edge", "value", mesh.loops, "edge_index", count, 1, np.int32))


def read_loop_triangles(mesh, corner_vertices):
    """Blender's triangulation of the faces: each triangle's corners (loops), face and vertices, (T, 3), (T,), (T, 3)
    int32. A mesh of triangles alone is its own: from 4.0 face i's corners are 3i, 3i + 1 and 3i + 2, and Blender's
    triangle of a triangle takes them in order, so nothing is computed or read (it was 15 ms of a 80,000-triangle
    cage's reading in 4.5). Other meshes read their triangles' corners and faces, and take the vertices from the
    corners'."""
    num_faces = len(mesh.polygons)
    if READS_ATTRIBUTES and len(mesh.loops) == 3 * num_faces:  # every face has three corners or more
        loops = np.arange(3 * num_faces, dtype=np.int32).reshape(num_faces, 3)
        return loops, np.arange(num_faces, dtype=np.int32), corner_vertices.reshape(num_faces, 3)
    mesh.calc_loop_triangles()
    triangles = mesh.loop_triangles
    count = len(triangles)
    # From 4.1 a MeshLoopTriangle points at its three corners in Blender's array of them; through RNA they are read a
    # triangle at a time (12 ms for a 40,000-quad cage in 4.5), as one block 0.1 ms. Their faces have an array of
    # their own from 4.0.
    block = memory_views.loop_triangle_corners(triangles)
    loops = block.copy() if block is not None else read_array(triangles, "loops", count, 3, np.int32)
    faces = mesh.loop_triangle_polygons if READS_ATTRIBUTES else triangles
    polygons = read_array(faces, "value" if READS_ATTRIBUTES else "polygon_index", count, 1, np.int32)
    # A triangle's vertices are its corners' (what MeshLoopTriangle.vertices reads, element by element).
    return loops, polygons, np.take(corner_vertices, loops)


# The edge marks and the attributes that hold them from 4.0.
_EDGE_FLAG_ATTRIBUTES = {"use_seam": SEAM_ATTRIBUTE if NAMES_SEAMS_AND_NORMALS else "." + SEAM_ATTRIBUTE,
                         "use_edge_sharp": "sharp_edge"}


def read_edge_flags(mesh):
    """The edges' seam and sharp marks, as {"use_seam": (E,) bool, "use_edge_sharp": (E,) bool}; from 4.0 boolean
    attributes, absent while no edge has the mark."""
    count = len(mesh.edges)
    if not READS_ATTRIBUTES:
        return {prop: read_array(mesh.edges, prop, count, 1, np.bool_) for prop in _EDGE_FLAG_ATTRIBUTES}
    return {prop: read_named_attribute(mesh, name, count, np.bool_) for prop, name in _EDGE_FLAG_ATTRIBUTES.items()}


def write_edge_flags(mesh, flags):
    """Marks on a new mesh's edges, read_edge_flags' keys each with (E,) bool: from 4.0 through their attributes, one
    block each, where MeshEdge's collection goes an edge at a time (160 ms for 1.9 million edges in 5.3); before, into
    the bits of their structs' flags where memory_views.edge_flag_bits finds them."""
    for prop, values in flags.items():
        values = np.ascontiguousarray(values, dtype=bool)
        if READS_ATTRIBUTES:
            name = _EDGE_FLAG_ATTRIBUTES[prop]
            attribute = mesh.attributes.get(name) or mesh.attributes.new(name, 'BOOLEAN', 'EDGE')
            attribute.data.foreach_set("value", values)
            continue
        bits = memory_views.edge_flag_bits(mesh.edges, prop)
        if bits is None:
            mesh.edges.foreach_set(prop, values)
        else:
            field, bit = bits  # in place: no temporaries of the edges' size
            np.bitwise_and(field, ~bit, out=field)
            np.bitwise_or(field, bit, out=field, where=values)


def read_face_materials_and_smooth(mesh):
    """Each face's material index, (F,) int32, and smooth shading, (F,) bool; from 4.0 attributes, absent while every
    face has material 0 or is smooth."""
    count = len(mesh.polygons)
    if not READS_ATTRIBUTES:
        return (read_array(mesh.polygons, "material_index", count, 1, np.int32),
                read_array(mesh.polygons, "use_smooth", count, 1, np.bool_))
    smooth = ~read_named_attribute(mesh, "sharp_face", count, np.bool_)
    return read_named_attribute(mesh, "material_index", count, np.int32), smooth


# From 4.0 a face is an offset into the corners: MeshPolygon points at the face's entry of the mesh's offsets (faces
# + 1 ints, the last the number of corners), and loop_start's setter writes that int. foreach_set writes through RNA a
# face at a time there (100 ms for 1.28 million faces in 4.5); set_triangle_loops does what the setters do, to the
# same ints, as one block.
FACES_ARE_OFFSETS = bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly


def set_triangle_loops(mesh):
    """Every face a triangle of the next three corners: face i's are 3i, 3i + 1 and 3i + 2."""
    count = len(mesh.polygons)
    block = memory_views.face_offsets(mesh.polygons) if FACES_ARE_OFFSETS else None
    if block is None:
        _write_legacy(mesh.polygons, "loop_start", np.arange(0, 3 * count, 3, dtype=np.int32))
        if not FACES_ARE_OFFSETS:
            _write_legacy(mesh.polygons, "loop_total", np.full(count, 3, dtype=np.int32))
        return
    # A chunk at a time: a small temporary is memory Blender's process reuses, one of the faces' size is fresh (5 MB
    # and page faults for 1.28 million faces).
    offsets = block.reshape(-1)
    for start in range(0, count, _OFFSETS_CHUNK):
        end = min(count, start + _OFFSETS_CHUNK)
        offsets[start:end] = np.arange(3 * start, 3 * end, 3, dtype=np.int32)


_OFFSETS_CHUNK = 1 << 16


def _attribute_view(mesh, name, count, width, ctype=ctypes.c_int32):
    """The attribute `name`'s array as a view of Blender's memory (memory_views.attribute_array), from 4.0; None
    before, or where the mesh has no such attribute or it cannot be viewed."""
    attribute = mesh.attributes.get(name) if READS_ATTRIBUTES else None
    return memory_views.attribute_array(attribute, count, width, ctype)
