"""Numpy-only mesh logic of the add-on: crease mapping, tags, edge look-ups and the layout of the subdivided mesh.

Nothing here imports bpy or the native module, so tests load this file on its own with plain Python.
"""

import numpy as np

# Blender's Subdivision Surface maps a crease weight c to an OpenSubdiv sharpness 10·c²
# (BKE_subdiv_crease_to_sharpness_f); 10 is OpenSubdiv's "infinitely sharp".
INFINITE_SHARPNESS = np.float32(10.0)

def crease_to_sharpness(weights):
    """Blender's own mapping, evaluated in float32 in the same order (c·c·10) so the sharpness is bit-identical."""
    w = np.asarray(weights, dtype=np.float32)
    return w * w * INFINITE_SHARPNESS


def sharpness_to_crease(sharpness):
    """Inverse of crease_to_sharpness, so that child sharpness written back as a weight round-trips."""
    s = np.clip(np.asarray(sharpness, dtype=np.float32), 0.0, INFINITE_SHARPNESS)
    return np.sqrt(s / INFINITE_SHARPNESS).astype(np.float32)


def crease_tags(edge_vertices, edge_weights, vertex_weights, rules, crease_threshold):
    """The core's tag arrays from Blender's crease weights.

    OpenSubdiv rules: every positive weight becomes the sharpness Blender would use (semi-sharp included).
    Seed rules: the weights themselves go to the core, which treats those at or above the threshold as creases and
    carries the weights to child edges; a vertex crease at or above the threshold marks a corner.
    """
    edge_weights = np.asarray(edge_weights, dtype=np.float32)
    vertex_weights = np.asarray(vertex_weights, dtype=np.float32)
    tagged_edges = np.flatnonzero(edge_weights > 0)
    if rules == 'OPENSUBDIV':
        corners = np.flatnonzero(vertex_weights > 0)
        edge_sharpness = crease_to_sharpness(edge_weights[tagged_edges])
        corner_sharpness = crease_to_sharpness(vertex_weights[corners])
    else:
        corners = np.flatnonzero((vertex_weights > 0) & (vertex_weights >= crease_threshold))
        edge_sharpness = edge_weights[tagged_edges]
        corner_sharpness = vertex_weights[corners]
    return {
        "crease_edges": np.ascontiguousarray(edge_vertices[tagged_edges], dtype=np.int32).reshape(-1, 2),
        "crease_sharpness": np.ascontiguousarray(edge_sharpness, dtype=np.float32),
        "corner_vertices": corners.astype(np.int32),
        "corner_sharpness": np.ascontiguousarray(corner_sharpness, dtype=np.float32),
    }


def child_crease_weights(sharpness, rules):
    """Crease weights for the child edges: OpenSubdiv's decremented sharpness mapped back through 10·c²; the seed's
    rules carry the weight itself."""
    if rules == 'OPENSUBDIV':
        return sharpness_to_crease(sharpness)
    return np.clip(np.asarray(sharpness, dtype=np.float32), 0.0, 1.0)


def limit_crease_weights(sharpness, rules):
    """Crease weights on the limit surface (a tessellation's edges and vertices) from the core's tags: the seed's
    rules carry the weight; OpenSubdiv's spend a semi-sharp crease before the limit, so only the infinitely sharp stay
    (as weight 1)."""
    if rules == 'OPENSUBDIV':
        return (np.asarray(sharpness) >= INFINITE_SHARPNESS).astype(np.float32)
    return child_crease_weights(sharpness, rules)


def edge_keys(pairs, num_vertices):
    """One int64 per undirected edge, so edges can be matched with sorting instead of dictionaries."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    return np.minimum(pairs[:, 0], pairs[:, 1]) * num_vertices + np.maximum(pairs[:, 0], pairs[:, 1])


def lookup_edges(table_pairs, query_pairs, num_vertices):
    """Index into table_pairs of each query edge (either direction), -1 where the table lacks it. The smaller side
    is sorted: a few crease edges are found among a million edges without sorting the million."""
    if not len(table_pairs) or not len(query_pairs):
        return np.full(len(query_pairs), -1, dtype=np.int64)
    table = edge_keys(table_pairs, num_vertices)
    query = edge_keys(query_pairs, num_vertices)
    if len(query) < len(table):
        unique, inverse = np.unique(query, return_inverse=True)
        pos = np.minimum(np.searchsorted(unique, table), len(unique) - 1)
        hit = unique[pos] == table
        found = np.full(len(unique), -1, dtype=np.int64)
        found[pos[hit]] = np.flatnonzero(hit)
        return found[inverse.ravel()]
    order = np.argsort(table, kind="stable")
    sorted_keys = table[order]
    pos = np.minimum(np.searchsorted(sorted_keys, query), len(table) - 1)
    return np.where(sorted_keys[pos] == query, order[pos], -1)


def take_rows(values, indices):
    """values' rows (along the first axis) at indices, in indices' shape: np.take, which copies a row at a time, where
    numpy's fancy indexing of rows of a few values copies value by value, 2-7 times slower on the millions of corners
    of a result (docs/benchmark.md, "an artist's mesh applied")."""
    return np.take(values, indices, axis=0)


def duplicate_triangles(triangles):
    """Pairs (first, later) of triangles with the same three vertices, in any order, in the order of the later one.

    Each triangle's three vertices, ordered by minimum and maximum (numpy's sort along rows of three is many times
    slower), become one integer where three vertex numbers fit in 63 bits (below 2 million vertices). Most meshes have
    no pair, which a plain sort of the integers shows at a fraction of the stable one that orders the pairs
    (docs/benchmark.md, "an artist's mesh applied")."""
    t = np.asarray(triangles).reshape(-1, 3)
    low = np.minimum(np.minimum(t[:, 0], t[:, 1]), t[:, 2]).astype(np.int64)
    high = np.maximum(np.maximum(t[:, 0], t[:, 1]), t[:, 2]).astype(np.int64)
    middle = t[:, 0] + t[:, 1].astype(np.int64) + t[:, 2] - low - high
    n = int(high.max(initial=0)) + 1
    if n ** 3 < 2 ** 63:
        keys = (low * n + middle) * n + high  # the three as one integer
        if not np.any(np.diff(np.sort(keys)) == 0):
            return np.empty((0, 2), dtype=np.intp)
        order = np.argsort(keys, kind="stable")  # equal triangles in the order of their indices
        ordered = keys[order]
        equal = ordered[1:] == ordered[:-1]
    else:
        keys = np.stack([low, middle, high], axis=1)
        order = np.lexsort(keys.T[::-1])
        ordered = keys[order]
        equal = _equal_rows(ordered[1:], ordered[:-1])
    later = np.flatnonzero(equal) + 1  # places equal to the one before
    starts = np.ones(len(order), dtype=bool)
    starts[later] = False
    first = order[np.maximum.accumulate(np.where(starts, np.arange(len(order)), 0))]  # each run's first triangle
    pairs = np.stack([first[later], order[later]], axis=1)
    return pairs[np.argsort(pairs[:, 1], kind="stable")]


def _equal_rows(x, y):
    """Where rows of x equal those of y, column by column: numpy's all() along short rows is many times slower."""
    equal = np.ones(len(x), dtype=bool)
    for column in range(x.shape[1]):
        equal &= x[:, column] == y[:, column]
    return equal


def side_edges(triangles, triangle_loops, loop_edges, edge_vertices):
    """For side k of each cage triangle (from corner k to k + 1), the mesh edge it runs along, -1 for a diagonal that
    Blender's triangulation of an n-gon added: (T, 3) int32, the numbers Plan.output_edge_parents takes. A triangle
    keeps its face's winding, so a side along the face's boundary is the edge of the loop at its first corner; a
    diagonal is not (that edge leads elsewhere). The loop's vertex is one end of its edge, so the exclusive or of the
    edge's two ends with it is the other end, the side's second corner where the side runs along the edge."""
    edges = np.take(loop_edges, triangle_loops)
    edge_vertices = np.asarray(edge_vertices).reshape(-1, 2)
    other_end = np.take(edge_vertices[:, 0] ^ edge_vertices[:, 1], edges) ^ triangles
    return np.where(other_end == triangles[:, [1, 2, 0]], edges, -1).astype(np.int32)


# How far a face point's parameters may be from a side of its triangle and still lie on it: parameters are multiples
# of 1 / rate (at most 4096) computed in float32, so an ulp's worth apart from the side, never 1e-4 apart.
_ON_SIDE = 1e-6


def tessellated_edge_sides(corner_face_points, face_point_parameters):
    """For edge k of each triangle of a tessellation (from corner k to k + 1), the side of its parent triangle it lies
    on, -1 inside: corner_face_points (T, 3) and face_point_parameters (P, 2), the Tessellation's, each face point's
    (u, v) in its triangle, side 0 running from corner 0 to 1 (v = 0), side 1 from 1 to 2 (u + v = 1), side 2 from 2
    to 0 (u = 0). Returns (T, 3) int8. The sides are found per face point and gathered per corner as bytes, not from
    each corner's parameters, 16 times the bytes."""
    u, v = face_point_parameters[:, 0], face_point_parameters[:, 1]
    on = (np.abs(v) < _ON_SIDE).view(np.uint8) | (np.abs(u + v - 1) < _ON_SIDE).view(np.uint8) << 1
    on |= (np.abs(u) < _ON_SIDE).view(np.uint8) << 2
    corners = np.take(on, corner_face_points)
    shared = corners & corners[:, [1, 2, 0]]  # both ends on one side: two corners share at most one
    return np.take(_SIDE_OF_FLAGS, shared)


_SIDE_OF_FLAGS = np.array([-1, 0, 1, -1, 2, -1, -1, -1], dtype=np.int8)  # the side of each single flag, else -1


def tessellated_edge_parents(triangle_edges, edge_sides, parent_triangles, side_edges, num_edges):
    """For each edge of a tessellation, the cage edge it lies on, -1 inside a cage triangle: triangle_edges (T, 3)
    from Tessellation.output_edges, edge_sides (T, 3) from tessellated_edge_sides, parent_triangles (T,), side_edges
    (T_cage, 3) from side_edges: the cage edge of each side of each cage triangle (-1 for a diagonal)."""
    parents = np.full(num_edges, -1, dtype=np.int64)
    on_side = np.flatnonzero(np.asarray(edge_sides).ravel() >= 0)  # triangle 3 t + k's edge k
    cage_sides = np.take(parent_triangles, on_side // 3) * 3 + np.take(edge_sides, on_side)
    parents[np.take(triangle_edges, on_side)] = np.take(side_edges, cage_sides)
    return parents


def interpolate_in_triangles(corner_values, parents, parameters):
    """Values at points of triangles, linearly from the corners: corner_values (T, 3, C) per triangle corner, parents
    (P,) each point's triangle, parameters (P, 2) its (u, v) there (corner 0 + u (corner 1 - corner 0) + v (corner 2
    - corner 0)). Returns (P, C) float32."""
    corners = take_rows(np.asarray(corner_values, dtype=np.float32), parents)
    u, v = parameters[:, 0:1], parameters[:, 1:2]
    return corners[:, 0] + u * (corners[:, 1] - corners[:, 0]) + v * (corners[:, 2] - corners[:, 0])


def edge_face_counts(loop_edges, num_edges):
    return np.bincount(loop_edges, minlength=num_edges)


# How each attribute type moves through foreach_get/foreach_set: (property, components, numpy type).
ATTRIBUTE_LAYOUT = {
    'FLOAT': ("value", 1, np.float32),
    'FLOAT2': ("vector", 2, np.float32),
    'FLOAT_VECTOR': ("vector", 3, np.float32),
    'FLOAT_COLOR': ("color", 4, np.float32),
    'BYTE_COLOR': ("color", 4, np.float32),
    'INT': ("value", 1, np.int32),
    'INT8': ("value", 1, np.int32),
    'BOOLEAN': ("value", 1, np.bool_),
}
INTERPOLATED_TYPES = {'FLOAT', 'FLOAT2', 'FLOAT_VECTOR', 'FLOAT_COLOR', 'BYTE_COLOR'}
# Refined as floats too, then brought back to their type (see from_refined), as Blender interpolates them.
DISCRETE_TYPES = {'INT', 'INT8', 'BOOLEAN'}


def plan_attributes(attributes, skip):
    """Sorts (name, domain, data_type) triples into what apply does with each: point attributes are refined with
    the vertex rules (integers rounded, booleans true where any contributing vertex is), corner ones of float types
    linearly per face (like UVs), face ones copied from the parent face, edge ones from the cage edge a child edge
    lies on (edges inside a cage face get zero / false, as in Subdivision Surface).
    Returns (point, corner, face, edge, dropped) lists of triples; names in skip and Blender's internal ones
    ('.'-prefixed) are left out (apply handles those itself)."""
    point, corner, face, edge, dropped = [], [], [], [], []
    for name, domain, data_type in attributes:
        if name in skip or name.startswith("."):
            continue
        if domain == 'POINT' and data_type in INTERPOLATED_TYPES | DISCRETE_TYPES:
            point.append((name, domain, data_type))
        elif domain == 'CORNER' and data_type in INTERPOLATED_TYPES:
            corner.append((name, domain, data_type))
        elif domain == 'FACE' and data_type in ATTRIBUTE_LAYOUT:
            face.append((name, domain, data_type))
        elif domain == 'EDGE' and data_type in ATTRIBUTE_LAYOUT:
            edge.append((name, domain, data_type))
        else:
            dropped.append((name, domain, data_type))
    return point, corner, face, edge, dropped


def shared_vertex_normals(triangles, corner_normals, num_vertices):
    """The normal of each vertex, (V, 3), when every corner of every vertex has the same one (bit for bit; no crease
    splits them): Blender then takes one normal per vertex, six times fewer values than one per corner. None when
    some vertex has corners with different normals. Vertices in no triangle get zero (Blender's own normal)."""
    vertices = np.asarray(triangles).reshape(-1)
    normals = np.asarray(corner_normals, dtype=np.float32).reshape(-1, 3)
    shared = np.zeros((num_vertices, 3), dtype=np.float32)
    shared[vertices] = normals
    return shared if np.array_equal(take_rows(shared, vertices), normals) else None


def triangle_normals(positions, triangles):
    """(T, 3) float32 unit normals of triangles (T, 3) of positions (V, 3), counter-clockwise facing out, as Blender's
    face normals (zero for a degenerate triangle)."""
    p = np.asarray(positions, dtype=np.float32)
    a, b, c = (p[triangles[:, k]] for k in range(3))
    return normalize(np.cross(b - a, c - a))


def normalize(vectors):
    """vectors (..., 3) float32 made unit in place (zero ones stay zero), and returned. Their lengths by einsum:
    numpy's norm along an axis of three took 11 ms of 730,000 corner normals, einsum 3 ms."""
    lengths = np.sqrt(np.einsum("...k,...k->...", vectors, vectors))[..., None]
    np.divide(vectors, lengths, out=vectors, where=lengths > 0)
    return vectors


def from_refined(values, data_type):
    """Refined float channels back to the attribute's type: integers rounded to the nearest, booleans true where
    any vertex with a positive weight was (every Loop weight of a contributing vertex is positive)."""
    if data_type == 'BOOLEAN':
        return values > 0.0
    if data_type in ('INT', 'INT8'):
        return np.rint(values).astype(np.int32)
    return values


def inherit_edge_values(values, parents, default=0):
    """Per child edge, the value of the cage edge it lies on (parents: its index, -1 inside a face), default inside
    faces: one gather from the values with the default after them, where -1 takes the last row (no mask of the
    million edges inside faces)."""
    values = np.asarray(values)
    table = np.concatenate([values, np.full((1,) + values.shape[1:], default, dtype=values.dtype)])
    return take_rows(table, parents)


def shared_positions(positions):
    """How many vertices sit exactly where another one does (split vertices: a crack that subdivision keeps open)."""
    if not len(positions):
        return 0
    # Rows compared as bits (adding 0 makes -0.0 equal 0.0). Most meshes have none: a hash of each row's bits says so
    # when no two are equal (equal rows hash alike), without the exact count's lexsort.
    bits = (np.asarray(positions, dtype=np.float32) + np.float32(0)).view(np.uint32).astype(np.uint64)
    hashes = (bits[:, 0] * np.uint64(0x9E3779B97F4A7C15) ^ bits[:, 1]) * np.uint64(0xBF58476D1CE4E5B9) ^ bits[:, 2]
    if not np.any(np.diff(np.sort(hashes)) == 0):
        return 0
    sorted_bits = bits[np.lexsort((bits[:, 2], bits[:, 0] << np.uint64(32) | bits[:, 1]))]
    return int(np.count_nonzero(_equal_rows(sorted_bits[1:], sorted_bits[:-1])))
