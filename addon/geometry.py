"""Numpy-only mesh logic of the add-on: crease mapping, tags, edge look-ups and the layout of the subdivided mesh.

Nothing here imports bpy or the native module, so tests load this file on its own with plain Python.
"""
from dataclasses import dataclass

import numpy as np

# Blender's Subdivision Surface maps a crease weight c to an OpenSubdiv sharpness 10·c²
# (BKE_subdiv_crease_to_sharpness_f); 10 is OpenSubdiv's "infinitely sharp".
INFINITE_SHARPNESS = np.float32(10.0)

RULES = {'HOPPE94': "hoppe94", 'OPENSUBDIV': "opensubdiv"}
BOUNDARY = {'SMOOTH': "edges", 'KEEP_CORNERS': "edges-and-corners"}


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


def crease_edge_mask(edge_weights, edge_face_counts, rules, crease_threshold, use_creases):
    """Edges the rules treat as creases at the first level: tagged creases and boundary or non-manifold edges."""
    mask = (edge_face_counts == 1) | (edge_face_counts > 2)
    if use_creases:
        tagged = edge_weights > 0
        if rules == 'HOPPE94':
            tagged &= edge_weights >= crease_threshold
        mask |= tagged
    return mask


def edge_keys(pairs, num_vertices):
    """One int64 per undirected edge, so edges can be matched with sorting instead of dictionaries."""
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    return np.minimum(pairs[:, 0], pairs[:, 1]) * num_vertices + np.maximum(pairs[:, 0], pairs[:, 1])


def lookup_edges(table_pairs, query_pairs, num_vertices):
    """Index into table_pairs of each query edge (either direction), -1 where the table lacks it."""
    table = edge_keys(table_pairs, num_vertices)
    query = edge_keys(query_pairs, num_vertices)
    if not len(table):
        return np.full(len(query), -1, dtype=np.int64)
    order = np.argsort(table, kind="stable")
    sorted_keys = table[order]
    pos = np.minimum(np.searchsorted(sorted_keys, query), len(table) - 1)
    return np.where(sorted_keys[pos] == query, order[pos], -1)


def degenerate_triangles(triangles):
    t = triangles
    return np.flatnonzero((t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 2] == t[:, 0]))


def duplicate_triangles(triangles):
    """Pairs (first, later) of triangles with the same three vertices, in any order."""
    keys = np.sort(triangles, axis=1)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    later = np.flatnonzero(first[inverse.ravel()] != np.arange(len(triangles)))
    return np.stack([first[inverse.ravel()[later]], later], axis=1)


def corner_barycentrics(num_triangles):
    """Face-varying channels that put each parent corner at a unit barycentric coordinate. Refined linearly they say
    where every child corner sits in its parent triangle: a zero coordinate means "on the opposite parent edge",
    exactly, because the linear refinement of zeros is zero."""
    return np.ascontiguousarray(np.broadcast_to(np.eye(3, dtype=np.float32), (num_triangles, 3, 3)))


def inherited_edges(child_triangles, child_parents, child_barycentrics, parent_triangles, parent_edge_flags,
                    parent_edge_vertices, num_parent_vertices):
    """Child edges that lie on a flagged parent edge (seams, sharp edges), as vertex pairs.

    child_barycentrics (M_out, 3, 3): each child corner's position in its parent triangle (see corner_barycentrics).
    parent_edge_flags (E,): flags of the parent mesh's edges, parent_edge_vertices (E, 2) their vertices.
    """
    flagged_keys = np.unique(edge_keys(parent_edge_vertices[parent_edge_flags], num_parent_vertices))
    if not len(flagged_keys):
        return np.zeros((0, 2), dtype=np.int32)
    on_zero = child_barycentrics == 0.0  # (M_out, corner, coordinate)
    sides = []
    for j in range(3):
        k = (j + 1) % 3
        shared = on_zero[:, j, :] & on_zero[:, k, :]  # both ends on the parent edge opposite that coordinate
        child_tri, coordinate = np.nonzero(shared)
        parent = parent_triangles[child_parents[child_tri]]
        parent_pairs = np.stack([parent[np.arange(len(parent)), (coordinate + 1) % 3],
                                 parent[np.arange(len(parent)), (coordinate + 2) % 3]], axis=1)
        keys = edge_keys(parent_pairs, num_parent_vertices)
        pos = np.minimum(np.searchsorted(flagged_keys, keys), len(flagged_keys) - 1)
        hit = flagged_keys[pos] == keys
        sides.append(child_triangles[child_tri[hit]][:, [j, k]])
    return np.concatenate(sides).astype(np.int32)


def edge_face_counts(loop_edges, num_edges):
    return np.bincount(loop_edges, minlength=num_edges)


@dataclass(frozen=True)
class Options:
    """Settings of one subdivision (the panel's, overridden by the operator's arguments)."""
    levels: int = 1
    rules: str = 'HOPPE94'
    crease_threshold: float = 0.5
    boundary: str = 'SMOOTH'
    use_creases: bool = True
    cone_group: str = ""

    def plan_keywords(self):
        """Keyword arguments of _loopsub.Plan for these settings (tags and cones come from the mesh)."""
        return {
            "rules": RULES[self.rules],
            "boundary": BOUNDARY[self.boundary],
            "crease_threshold": float(self.crease_threshold) if self.rules == 'HOPPE94' else 0.0,
        }


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


def plan_attributes(attributes, skip):
    """Sorts (name, domain, data_type) triples into what apply does with each: point attributes of float types are
    refined with the vertex rules, corner ones linearly per face (like UVs), face ones copied from the parent face.
    Returns (point, corner, face, dropped) lists of triples; names in skip and Blender's internal ones ('.'-prefixed)
    are left out (apply handles those itself)."""
    point, corner, face, dropped = [], [], [], []
    for name, domain, data_type in attributes:
        if name in skip or name.startswith("."):
            continue
        if domain == 'POINT' and data_type in INTERPOLATED_TYPES:
            point.append((name, domain, data_type))
        elif domain == 'CORNER' and data_type in INTERPOLATED_TYPES:
            corner.append((name, domain, data_type))
        elif domain == 'FACE' and data_type in ATTRIBUTE_LAYOUT:
            face.append((name, domain, data_type))
        else:
            dropped.append((name, domain, data_type))
    return point, corner, face, dropped


def shared_positions(positions):
    """How many vertices sit exactly where another one does (split vertices: a crack that subdivision keeps open)."""
    if not len(positions):
        return 0
    return len(positions) - len(np.unique(positions, axis=0))
