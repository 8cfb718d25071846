"""The few places where Blender 3.x and 4.x differ for this add-on, behind one interface.

Blender 4.0 moved edge and vertex creases from dedicated layers (MeshEdge.crease, Mesh.edge_creases,
Mesh.vertex_creases, bmesh's crease layers) to the generic float attributes "crease_edge" and "crease_vert",
made MeshPolygon.loop_total read-only (face sizes follow from loop_start) and moved node group sockets to
NodeTree.interface; 4.1 dropped Auto Smooth, so that custom split normals and marked sharp edges always shade, and
replaced Mesh.calc_normals_split / MeshLoop.normal with Mesh.corner_normals. After 5.0 a Geometry Nodes modifier
keeps its inputs' values in RNA (modifier.properties.inputs) instead of ID properties of the modifier.

Normals and shading: 4.0 has Mesh.corner_normals but fills it only after calc_normals_split(); 4.1 converts the Auto
Smooth of files saved before it into appended "Auto Smooth" modifiers; 4.5 keeps UV seams in the attribute "uv_seam"
and custom normals in "custom_normal" (tangent space, or "free" float vectors), which apply must not copy as generic
attributes.
"""
import ctypes
import math

import bpy
import numpy as np

from .mesh_data import read_array

USES_CREASE_ATTRIBUTES = bpy.app.version >= (4, 0, 0)
EDGE_CREASE_ATTRIBUTE = "crease_edge"
VERTEX_CREASE_ATTRIBUTE = "crease_vert"


def _read_attribute(mesh, name, domain_size, dtype=np.float32):
    """The generic attribute `name`'s values, zero (False) where the mesh has none."""
    values = np.zeros(domain_size, dtype=dtype)
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


# Free normals: Blender shades with them as they are (4.5+); set_custom_normals writes them with one copy, where
# tangent-space normals cost Blender's normal spaces on every write (docs/benchmark.md, by version).
HAS_FREE_NORMALS = NAMES_SEAMS_AND_NORMALS


def has_free_normals(mesh):
    """Whether the mesh shades with free custom normals (4.5+): a float vector "custom_normal", on any domain."""
    attribute = mesh.attributes.get(CUSTOM_NORMAL_ATTRIBUTE) if NAMES_SEAMS_AND_NORMALS else None
    return attribute is not None and attribute.data_type == 'FLOAT_VECTOR'


# Where the mesh's own arrays are generic attributes (4.2.23 and later here: "position", ".edge_verts",
# ".corner_vert", ".corner_edge"; 3.4.1 has MVert, MEdge and MLoop), foreach_set on the attribute copies the array in
# one block: 25-100 times faster than the legacy collections (MeshVertex.co, MeshEdge.vertices, MeshLoop.vertex_index
# and edge_index), which go element by element (docs/benchmark.md, Apply). The attributes are looked up by name: a
# name beginning with "." is Blender's own, and 3.4 keeps no generic layer named "position".
def _write_array(mesh, name, prop, legacy, legacy_prop, values):
    """values into the attribute `name` (its `prop`) where the mesh keeps one, else into the legacy collection's
    legacy_prop (its structs' field in place where it can: _struct_field)."""
    attribute = mesh.attributes.get(name)
    if attribute is None:
        _write_legacy(legacy, legacy_prop, values)
    elif not _holds(attribute, values):
        attribute.data.foreach_set(prop, values)


def _write_legacy(collection, prop, values):
    """values into a legacy collection's prop: into its structs' field where _struct_field views it, else through
    foreach_set."""
    field = _struct_field(collection, prop)
    if field is None:
        collection.foreach_set(prop, values)
    else:
        field[...] = values.reshape(field.shape)


# Before 3.6 (3.4.1 here) edges, corners and faces are arrays of structs (MEdge: v1, v2, then flags; MLoop: v, e;
# MPoly: loopstart, totloop, then material and flags), whose integer fields foreach_get and foreach_set move one element
# at a time through RNA: 200-650 ms a field for a 1.28-million-triangle result in 3.4.1, a copy as a view of the
# structs (docs/benchmark.md). Per (item type, property): the struct's size in int32s, its field's first int32, and
# how many. Where the items' pointers are not such an array (other versions), the collection's own accessors remain.
_STRUCT_FIELDS = {("MeshEdge", "vertices"): (3, 0, 2), ("MeshLoop", "vertex_index"): (2, 0, 1),
                  ("MeshLoop", "edge_index"): (2, 1, 1), ("MeshPolygon", "loop_start"): (3, 0, 1),
                  ("MeshPolygon", "loop_total"): (3, 1, 1)}


def _struct_field(collection, prop):
    """The int32 field `prop` of a collection's structs (_STRUCT_FIELDS), as a (count, width) view of Blender's memory;
    None for other properties, versions or collections."""
    count = len(collection)
    layout = _STRUCT_FIELDS.get((collection[0].rna_type.identifier, prop)) if count else None
    if layout is None:
        return None
    size, first, width = layout
    block = _block_at(collection, count, size)
    return None if block is None else block[:, first:first + width]


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
    edge_block = _attribute_block(mesh, ".edge_verts", len(mesh.edges), 2)
    corner_edge_block = _attribute_block(mesh, ".corner_edge", len(mesh.loops), 1)
    corner_vertex_block = _attribute_block(mesh, ".corner_vert", len(mesh.loops), 1)
    if edge_block is None or corner_edge_block is None or corner_vertex_block is None:
        return None
    return edge_block, corner_edge_block.reshape(-1), corner_vertex_block.reshape(-1)


def position_array(mesh):
    """Blender's own array of a new mesh's vertex positions, as a writable (V, 3) float32 view of its memory for the
    core to evaluate into (as edge_arrays), or None: 3.4 keeps positions in MVert structs among other fields."""
    return _attribute_block(mesh, "position", len(mesh.vertices), 3, ctypes.c_float)


def free_vertex_normal_array(mesh):
    """A new mesh's free normals, one per vertex (HAS_FREE_NORMALS): its new point attribute "custom_normal", as a
    writable (V, 3) float32 view of its memory for the core to evaluate into; set_custom_normals then finds them in
    place. None before 4.5 (no attribute added), or where the attribute's items are not one array (the attribute
    stays, for set_custom_normals to fill)."""
    if not HAS_FREE_NORMALS:
        return None
    attribute = mesh.attributes.new(CUSTOM_NORMAL_ATTRIBUTE, 'FLOAT_VECTOR', 'POINT')
    return _block_at(attribute.data, len(mesh.vertices), 3, ctypes.c_float)


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
    field = _struct_field(legacy, legacy_prop) if dtype == np.int32 else None
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
    block = _block_at(triangles, count, 3)
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
    return {prop: _read_attribute(mesh, name, count, np.bool_) for prop, name in _EDGE_FLAG_ATTRIBUTES.items()}


def write_edge_flags(mesh, flags):
    """Marks on a new mesh's edges, read_edge_flags' keys each with (E,) bool: from 4.0 through their attributes, one
    block each, where MeshEdge's collection goes an edge at a time (160 ms for 1.9 million edges in 5.3); before, into
    the bits of their structs' flags where _edge_flag_bits finds them."""
    for prop, values in flags.items():
        values = np.ascontiguousarray(values, dtype=bool)
        if READS_ATTRIBUTES:
            name = _EDGE_FLAG_ATTRIBUTES[prop]
            attribute = mesh.attributes.get(name) or mesh.attributes.new(name, 'BOOLEAN', 'EDGE')
            attribute.data.foreach_set("value", values)
            continue
        bits = _edge_flag_bits(mesh.edges, prop)
        if bits is None:
            mesh.edges.foreach_set(prop, values)
        else:
            field, bit = bits  # in place: no temporaries of the edges' size
            np.bitwise_and(field, ~bit, out=field)
            np.bitwise_or(field, bit, out=field, where=values)


# Before 4.0 (3.4.1 here) an edge's seam and sharp marks are bits of MEdge's 16-bit flag, its struct's last field (v1,
# v2, crease and bevel weight bytes, flag: 12 bytes), which foreach_set sets an edge at a time (36 ms a mark for 1.9
# million edges in 3.4.1). Per mark, the bit (3.4's ME_SEAM and ME_SHARP).
_EDGE_FLAG_BITS = {"use_seam": 1 << 2, "use_edge_sharp": 1 << 9}


def _edge_flag_bits(edges, prop):
    """The flags of a new mesh's edges, (E,) int16 as a view of their structs, and prop's bit in them; None where the
    edges are not such an array, or where prop's setter does not turn that bit of the first edge (a version that
    keeps the mark elsewhere, as later ones keep it in an attribute). The check leaves the edge as it was."""
    bit = _EDGE_FLAG_BITS[prop]
    block = _block_at(edges, len(edges), 6, ctypes.c_int16)
    if block is None:
        return None
    field, first = block[:, 5], edges[0]
    before, marked = int(field[0]), getattr(first, prop)
    setattr(first, prop, not marked)
    turned = int(field[0]) ^ before
    setattr(first, prop, marked)
    return (field, np.int16(bit)) if turned == bit and int(field[0]) == before else None


def read_face_materials_and_smooth(mesh):
    """Each face's material index, (F,) int32, and smooth shading, (F,) bool; from 4.0 attributes, absent while every
    face has material 0 or is smooth."""
    count = len(mesh.polygons)
    if not READS_ATTRIBUTES:
        return (read_array(mesh.polygons, "material_index", count, 1, np.int32),
                read_array(mesh.polygons, "use_smooth", count, 1, np.bool_))
    smooth = ~_read_attribute(mesh, "sharp_face", count, np.bool_)
    return _read_attribute(mesh, "material_index", count, np.int32), smooth


# From 4.0 a face is an offset into the corners: MeshPolygon points at the face's entry of the mesh's offsets (faces
# + 1 ints, the last the number of corners), and loop_start's setter writes that int. foreach_set writes through RNA a
# face at a time there (100 ms for 1.28 million faces in 4.5); set_triangle_loops does what the setters do, to the
# same ints, as one block.
FACES_ARE_OFFSETS = bpy.types.MeshPolygon.bl_rna.properties["loop_total"].is_readonly


def set_triangle_loops(mesh):
    """Every face a triangle of the next three corners: face i's are 3i, 3i + 1 and 3i + 2."""
    count = len(mesh.polygons)
    block = _block_at(mesh.polygons, count, 1) if FACES_ARE_OFFSETS else None
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


def _block_at(collection, count, width, ctype=ctypes.c_int32):
    """The values behind the first `count` items of a collection of structs over one array, items of `width` values
    of ctype, as a (count, width) view of Blender's memory; None where the items' pointers say they are not such an
    array. An item's pointer (as_pointer) is its element's address in the array the collection's lookup goes
    through, so the first and the last item's bound the block."""
    if count < 2:
        return None
    step = width * ctypes.sizeof(ctype)
    first = collection[0].as_pointer()
    if collection[1].as_pointer() != first + step or collection[count - 1].as_pointer() != first + (count - 1) * step:
        return None
    return np.ctypeslib.as_array((ctype * (count * width)).from_address(first)).reshape(count, width)


def _attribute_block(mesh, name, count, width, ctype=ctypes.c_int32):
    """The attribute `name`'s array as _block_at's view, from 4.0 (attributes whose items point at their elements);
    None before, or where the mesh has no such attribute or its items are not one array."""
    attribute = mesh.attributes.get(name) if READS_ATTRIBUTES else None
    return None if attribute is None else _block_at(attribute.data, count, width, ctype)


def _holds(attribute, values):
    """Whether values (contiguous) are the attribute's own array, written in place by the core (position_array,
    free_vertex_normal_array): then there is nothing to copy."""
    return (len(values) > 0 and len(attribute.data) > 0
            and values.__array_interface__["data"][0] == attribute.data[0].as_pointer())


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


def show_result_field(group, result_socket, show):
    """Shows (or hides again) the group input's field in the modifier's panel, where the version hides it
    (hide_geometry_nodes_fields) and has no Warning node to say that the add-on is missing (4.0 to 4.2): in a file saved
    without results, the field names the placeholder object, "Add-on off"."""
    socket = group.interface.items_tree.get(result_socket) if hasattr(group, "interface") else None
    if socket is not None and hasattr(socket, "hide_in_modifier") and not HAS_WARNING_NODE:
        socket.hide_in_modifier = not show


# Handlers Blender runs when writing a file failed, where it has them: as after saving, the results go back.
SAVE_FAILED_HANDLERS = tuple(name for name in ("save_post_fail",) if hasattr(bpy.app.handlers, name))


def subdivision_set_arguments(**arguments):
    """The arguments Blender's object.subdivision_set (Ctrl 0-5) takes, of those given: level and relative in every
    version, ensure_modifier (hidden: add a Subdivision Surface where there is none) from 4.5 (4.5.15 and later here;
    3.4.1 and 4.2.23 have no such argument)."""
    known = bpy.ops.object.subdivision_set.get_rna_type().properties.keys()
    return {name: value for name, value in arguments.items() if name in known}


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


def set_modifier_input(modifier, name, value):
    """Sets the value a Geometry Nodes modifier gives its node group's input called name (see modifier_input for
    where each version keeps it)."""
    values, rna = _modifier_input_values(modifier)
    key = group_input_identifier(modifier.node_group, name)
    if rna:
        getattr(values, key).value = value
    else:
        values[key] = value


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


def own_corner_normals(mesh):
    """The normals Blender gives a mesh's corners of itself, (L, 3) float32: split at marked sharp edges, the face
    normal on a flat face. Free normals it has go first (4.5+: a result's own, written again after)."""
    existing = mesh.attributes.get(CUSTOM_NORMAL_ATTRIBUTE) if NAMES_SEAMS_AND_NORMALS else None
    if existing is not None:
        mesh.attributes.remove(existing)
    return read_corner_normals(mesh)


def read_corner_normals(mesh):
    """The normal Blender shades each corner (loop) with, custom split normals included: (L, 3) float32.

    4.1+ has them in Mesh.corner_normals; up to 4.0 Mesh.calc_normals_split() computes them into MeshLoop.normal.
    4.0 has Mesh.corner_normals too, but it is empty until calc_normals_split() has run (its length is that of the
    CD_NORMAL layer, rna_mesh.cc), so the version decides, not hasattr, and a length that is not the number of corners
    takes the old way as well. No 4.0 is installed here: that branch is read from Blender's sources, not tested.

    Free normals (4.5+) are read from their attribute, spread to the corners: that is what Blender shades with
    (Mesh.corner_normals gives the attribute's values as they are, unnormalised, whatever the faces' smooth flags),
    and Mesh.corner_normals of a copy from Object.to_mesh() of a mesh with free corner normals, what the live entry
    reads its input from, gave stale memory at a few corners in 4.5.15 and 5.0.1 (zeros, denormals, NaN; not seen in
    5.2.3)."""
    free = _free_corner_normals(mesh)
    if free is not None:
        return free
    values = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    corner_normals = getattr(mesh, "corner_normals", None) if bpy.app.version >= (4, 1, 0) else None
    if corner_normals is not None and len(corner_normals) == len(mesh.loops):
        corner_normals.foreach_get("vector", values)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", values)
        mesh.free_normals_split()
    return values.reshape(-1, 3)


def _free_corner_normals(mesh):
    """The free normals of mesh per corner (L, 3) float32, or None when it has none on the point, face or corner
    domain."""
    if not has_free_normals(mesh):
        return None
    attribute = mesh.attributes[CUSTOM_NORMAL_ATTRIBUTE]
    if attribute.domain not in ('POINT', 'FACE', 'CORNER'):
        return None
    values = np.empty(len(attribute.data) * 3, dtype=np.float32)
    attribute.data.foreach_get("vector", values)
    values = values.reshape(-1, 3)
    if attribute.domain == 'POINT':
        corner_vertices = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", corner_vertices)
        return values[corner_vertices]
    if attribute.domain == 'FACE':  # faces hold their corners in order (offsets) from 4.0 on
        sizes = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_total", sizes)
        return np.repeat(values, sizes, axis=0)
    return values


def set_custom_normals(mesh, normals, vertex_normals=None, free=False):
    """Custom normals: one per corner, normals (L, 3), or, when every corner of a vertex has the same one,
    vertex_normals (V, 3) (normals may then be None).

    In tangent space (every version; normals_split_custom_set and its _from_vertices, which encode each normal in
    its corner's normal space, and take one per vertex several times faster): a zero vector keeps Blender's own
    normal at that corner. Up to 4.0 they show only with Auto Smooth, which this turns on; a mesh that had it off
    gets the widest angle, so that only marked sharp edges (and the normals themselves) split the shading. Blender
    marks the edges sharp where the normals of one smooth fan differ (across creases).

    free (HAS_FREE_NORMALS, 4.5+): the normals (unit vectors) go as they are into the float vector attribute
    "custom_normal", on the point domain (vertex_normals) or the corner domain: free normals, which Blender shades
    with as they are (flat faces and marked sharp edges do not change them), and which cost a copy of the array, or
    nothing where they are the attribute's own (free_vertex_normal_array; the cage's own free normals are carried
    over so, and the limit normals go so where the version has them). Otherwise
    a free "custom_normal" the mesh has goes first: normals_split_custom_set leaves a mesh with free normals
    unchanged (4.5.15, 5.0.1, 5.2.3)."""
    existing = mesh.attributes.get(CUSTOM_NORMAL_ATTRIBUTE) if NAMES_SEAMS_AND_NORMALS else None
    if free:
        domain = 'POINT' if vertex_normals is not None else 'CORNER'
        values = vertex_normals if vertex_normals is not None else normals
        if existing is not None and (existing.data_type, existing.domain) != ('FLOAT_VECTOR', domain):
            mesh.attributes.remove(existing)
            existing = None
        if existing is None:
            existing = mesh.attributes.new(CUSTOM_NORMAL_ATTRIBUTE, 'FLOAT_VECTOR', domain)
        values = np.ascontiguousarray(values, dtype=np.float32).ravel()
        if not _holds(existing, values):
            existing.data.foreach_set("vector", values)
        return
    if existing is not None and existing.data_type == 'FLOAT_VECTOR':
        mesh.attributes.remove(existing)
    shade_sharp_edges(mesh)
    if vertex_normals is not None:
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(vertex_normals, dtype=np.float32))
    else:
        mesh.normals_split_custom_set(np.ascontiguousarray(normals, dtype=np.float32).reshape(-1, 3))


# Blender 4.1 dropped Auto Smooth. Opening a file saved before 4.1, it appends a Geometry Nodes modifier "Auto Smooth"
# (running a node group of its own making, shared by all) to every mesh object whose mesh had Auto Smooth on and no
# custom normals (BKE_main_mesh_legacy_convert_auto_smooth): to an entry's owner after the entry, and to the entry's
# hidden helper when the result saved had Blender's own normals (the helper's mesh took the cage's Auto Smooth, or
# Auto Smooth at 180 degrees). Seen in 4.2.23, 4.5.15, 5.0.1 and 5.2.3 on a file saved by 3.4.1.
_AUTO_SMOOTH_NODES = sorted((
    "NodeGroupOutput", "NodeGroupInput", "NodeGroupInput", "GeometryNodeSetShadeSmooth", "GeometryNodeSetShadeSmooth",
    "GeometryNodeInputMeshEdgeAngle", "GeometryNodeInputEdgeSmooth", "GeometryNodeInputShadeSmooth",
    "FunctionNodeBooleanMath", "FunctionNodeCompare"))


def converted_auto_smooth():
    """Whether the file just opened had its Auto Smooth converted to modifiers: saved before 4.1, open in 4.1+."""
    return bpy.app.version >= (4, 1, 0) and tuple(bpy.data.version) < (4, 1, 0)


def auto_smooth_modifiers(obj):
    """The modifiers of obj that run the node group Blender 4.1+ makes when it converts Auto Smooth on loading a file
    (recognised by its nodes, as Blender's own is_auto_smooth_node_tree does; the "Smooth by Angle" asset that Shade
    Auto Smooth adds is another group). Empty before 4.1."""
    if bpy.app.version < (4, 1, 0):
        return []
    return [modifier for modifier in obj.modifiers
            if modifier.type == 'NODES' and modifier.node_group is not None
            and sorted(node.bl_idname for node in modifier.node_group.nodes) == _AUTO_SMOOTH_NODES]
