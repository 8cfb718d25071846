"""Views of Blender's own memory: the one module of the add-on that reads or writes it through addresses
(`as_pointer`) instead of Blender's accessors, for the arrays those move an element at a time or would copy.

The contract:

- A view is a numpy array over memory Blender owns, made from the items of one collection, and only where the items'
  addresses say they lie in one array at the stated item size (the first, second and last item are compared), and
  where the view reads at its first and last item what Blender's own accessor reads there. A layout that differs in
  some version shows there, and no view is made: each function returns None.
- A view is valid while its collection is not resized and its mesh not freed: a caller uses it at once and keeps it
  nowhere.
- Every caller has a path through Blender's accessors for None: a view is a speed-up, never the only way. With
  `enabled` False (the environment variable LOOP_SUBDIVISION_MEMORY_VIEWS=0 when the add-on loads sets it) every
  function here returns None, so that the add-on moves every array through Blender's accessors; the tests build the
  same meshes both ways and compare them (tests/blender/test_memory_views.py).

Where each view pays (docs/benchmark.md, Apply): 3.4's edges, corners and faces are arrays of structs whose integer
fields foreach_get and foreach_set move an element at a time; 4.0 and later keep mesh arrays as attributes whose items
point at their elements, so the core can evaluate straight into a new mesh's own arrays.
"""
import ctypes
import os

import numpy as np

enabled = os.environ.get("LOOP_SUBDIVISION_MEMORY_VIEWS", "1") != "0"

# Before 3.6 (3.4.1 here) edges, corners and faces are arrays of structs (MEdge: v1, v2, then flags; MLoop: v, e;
# MPoly: loopstart, totloop, then material and flags). Per (item type, property): the struct's size in int32s, its
# field's first int32, and how many.
_STRUCT_FIELDS = {("MeshEdge", "vertices"): (3, 0, 2), ("MeshLoop", "vertex_index"): (2, 0, 1),
                  ("MeshLoop", "edge_index"): (2, 1, 1), ("MeshPolygon", "loop_start"): (3, 0, 1),
                  ("MeshPolygon", "loop_total"): (3, 1, 1)}

# Before 4.0 (3.4.1 here) an edge's seam and sharp marks are bits of MEdge's 16-bit flag, its struct's last field (v1,
# v2, crease and bevel weight bytes, flag: 12 bytes). Per mark, the bit (3.4's ME_SEAM and ME_SHARP).
_EDGE_FLAG_BITS = {"use_seam": 1 << 2, "use_edge_sharp": 1 << 9}


def _block(collection, count, width, ctype):
    """The values behind the first `count` items of a collection of structs over one array, items of `width` values
    of ctype, as a (count, width) view; None where the items' addresses say they are not such an array. An item's
    address is its element's in the array the collection's lookup goes through, so the first and the last item's
    bound the block."""
    if not enabled or count < 2:
        return None
    step = width * ctypes.sizeof(ctype)
    first = collection[0].as_pointer()
    if collection[1].as_pointer() != first + step or collection[count - 1].as_pointer() != first + (count - 1) * step:
        return None
    return np.ctypeslib.as_array((ctype * (count * width)).from_address(first)).reshape(count, width)


def _reads_as(view, read_item):
    """view, where its first and last rows hold what read_item(index) (Blender's accessor) reads; else None."""
    if view is None:
        return None
    last = len(view) - 1
    agree = all(np.array_equal(view[index].ravel(), np.ravel(read_item(index))) for index in (0, last))
    return view if agree else None


def struct_field(collection, prop):
    """The int32 field `prop` of a collection's structs (3.4's MEdge, MLoop, MPoly), as a (count, width) view; None for
    other properties, versions or collections."""
    count = len(collection)
    layout = _STRUCT_FIELDS.get((collection[0].rna_type.identifier, prop)) if count else None
    if layout is None:
        return None
    size, first, width = layout
    block = _block(collection, count, size, ctypes.c_int32)
    view = None if block is None else block[:, first:first + width]
    return _reads_as(view, lambda index: getattr(collection[index], prop))


def edge_flag_bits(edges, prop):
    """The flags of a new mesh's edges (3.4's MEdge), (E,) int16 as a view, and prop's bit in them; None where the
    edges are not such an array, or where prop's setter does not turn that bit of the first edge (a version that keeps
    the mark elsewhere, as later ones keep it in an attribute). The check leaves the edge as it was."""
    block = _block(edges, len(edges), 6, ctypes.c_int16)
    if block is None:
        return None
    bit = _EDGE_FLAG_BITS[prop]
    field, first = block[:, 5], edges[0]
    before, marked = int(field[0]), getattr(first, prop)
    setattr(first, prop, not marked)
    turned = int(field[0]) ^ before
    setattr(first, prop, marked)
    return (field, np.int16(bit)) if turned == bit and int(field[0]) == before else None


def attribute_array(attribute, count, width, ctype=ctypes.c_int32):
    """A generic attribute's values (4.0 and later: its items point at their elements), (count, width) as a view; None
    for no attribute, or where its items are not one array."""
    if attribute is None:
        return None
    prop = "vector" if attribute.data_type in ('FLOAT_VECTOR', 'FLOAT2') else "value"
    return _reads_as(_block(attribute.data, count, width, ctype), lambda index: getattr(attribute.data[index], prop))


def loop_triangle_corners(triangles):
    """Each of Blender's triangles' three corners (4.1 and later: a MeshLoopTriangle points at them in Blender's array
    of them), (T, 3) int32 as a view; None where they are not one array."""
    return _reads_as(_block(triangles, len(triangles), 3, ctypes.c_int32), lambda index: triangles[index].loops[:])


def face_offsets(polygons):
    """The faces' offsets into the corners (4.0 and later: MeshPolygon points at the face's entry of the mesh's
    offsets, which loop_start's setter writes), (F, 1) int32 as a view; None where they are not one array."""
    return _reads_as(_block(polygons, len(polygons), 1, ctypes.c_int32), lambda index: polygons[index].loop_start)


def holds(attribute, values):
    """Whether values (contiguous) are the attribute's own array (a view of it the core wrote into): then there is
    nothing to copy."""
    return (len(values) > 0 and len(attribute.data) > 0
            and values.__array_interface__["data"][0] == attribute.data[0].as_pointer())
