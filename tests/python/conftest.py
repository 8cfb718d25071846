"""Shared meshes and hand-written references for the tests of the `_loopsub` module.

Nothing here calls the project's code to produce an expected value: the references below are Loop's masks
written out from RULES.md section 1, in plain numpy.
"""
import math

import numpy as np
import pytest

import _loopsub  # noqa: F401  (imported here so that a missing module fails every test with one clear error)


# ---------------------------------------------------------------------------------------------------------------
# Meshes


def tetrahedron():
    """Regular tetrahedron centred at the origin, outward counter-clockwise faces. Every vertex has valence 3."""
    positions = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], np.float32)
    triangles = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], np.int32)
    return positions, triangles


def icosahedron():
    """Regular icosahedron, outward counter-clockwise faces. Every vertex has valence 5."""
    t = (1 + 5**0.5) / 2
    positions = np.array(
        [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t],
         [0, -1, -t], [0, 1, -t], [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], np.float32)
    triangles = np.array(
        [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
         [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
         [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]], np.int32)
    return positions, triangles


def grid(n, seed=0, height=0.0):
    """An n x n vertex grid in the unit square, two triangles per cell, z randomised by `height`."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    z = height * rng.standard_normal((n, n))
    positions = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(n - 1))
    v = (j * n + i).ravel()
    triangles = np.concatenate([np.stack([v, v + 1, v + n + 1], 1), np.stack([v, v + n + 1, v + n], 1)])
    return positions, triangles.astype(np.int32)


def hexagon_disk(perturb=True):
    """Centre vertex 0 with six rim vertices 1..6 and six triangles (0, i, i+1): an open disk.

    The centre is interior with valence 6; every rim vertex is on the boundary with valence 3. The positions are
    perturbed so that different masks give different points.
    """
    angles = np.arange(6) * (math.pi / 3)
    rim = np.stack([np.cos(angles), np.sin(angles), np.zeros(6)], 1)
    positions = np.vstack([[0.0, 0.0, 0.0], rim])
    if perturb:
        positions += np.random.default_rng(7).uniform(-0.15, 0.15, positions.shape)
    triangles = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)], np.int32)
    return positions.astype(np.float32), triangles


def boundary_fan():
    """A half fan: vertex 0 with rim 1..4 and triangles (0,1,2), (0,2,3), (0,3,4), all in one plane, perturbed.

    Vertex 0 is a boundary vertex with valence 4 (three faces) whose two crease edges are the boundary edges 0-1
    and 0-4: a *regular* boundary crease vertex. Vertices 1 and 4 are boundary vertices of valence 2, 2 and 3 of
    valence 3: irregular crease vertices.
    """
    angles = np.linspace(0, math.pi, 4)
    rim = np.stack([np.cos(angles), np.sin(angles), np.zeros(4)], 1)
    positions = np.vstack([[0.0, 0.0, 0.0], rim]) + np.random.default_rng(3).uniform(-0.1, 0.1, (5, 3))
    triangles = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 4]], np.int32)
    return positions.astype(np.float32), triangles


# ---------------------------------------------------------------------------------------------------------------
# Loop's constants and a hand-written reference for smooth closed meshes (RULES.md section 1)


def loop_b(n):
    return (3 + 2 * math.cos(2 * math.pi / n)) / 8


def loop_a(n):
    return 5 / 8 - loop_b(n) ** 2


def edges_of(triangles):
    """Sorted unique undirected edges (a < b) of a triangle list, and for each the opposite vertices."""
    opposite = {}
    for a, b, c in np.asarray(triangles).tolist():
        for u, v, w in ((a, b, c), (b, c, a), (c, a, b)):
            opposite.setdefault((min(u, v), max(u, v)), []).append(w)
    return opposite


def neighbours_of(triangles, n):
    ring = [set() for _ in range(n)]
    for a, b, c in np.asarray(triangles).tolist():
        for u, v in ((a, b), (b, c), (c, a)):
            ring[u].add(v)
            ring[v].add(u)
    return ring


def smooth_loop_reference(positions, triangles):
    """One level of Loop subdivision of a closed mesh with no tags, in float64.

    Returns (vertex points (N, 3), {edge (a, b) with a < b: edge point}). Vertex: (1 - a(n)) v + a(n)/n * sum of
    the ring; edge: 3/8 (A + B) + 1/8 (C + D).
    """
    p = np.asarray(positions, np.float64)
    ring = neighbours_of(triangles, len(p))
    vertex_points = np.empty_like(p)
    for i, nbrs in enumerate(ring):
        n = len(nbrs)
        vertex_points[i] = (1 - loop_a(n)) * p[i] + loop_a(n) / n * p[sorted(nbrs)].sum(0)
    edge_points = {}
    for (a, b), opp in edges_of(triangles).items():
        assert len(opp) == 2, "the reference is for closed manifold meshes"
        edge_points[(a, b)] = 3 / 8 * (p[a] + p[b]) + 1 / 8 * (p[opp[0]] + p[opp[1]])
    return vertex_points, edge_points


def reference_loop_mesh(positions, triangles, levels):
    """`levels` levels of smooth Loop subdivision of a closed untagged mesh, with its own vertex order."""
    p, t = np.asarray(positions, np.float64), np.asarray(triangles)
    for _ in range(levels):
        vertex_points, edge_points = smooth_loop_reference(p, t)
        index = {e: len(p) + k for k, e in enumerate(edge_points)}
        p = np.vstack([vertex_points, np.array(list(edge_points.values())).reshape(-1, 3)])
        children = []
        for a, b, c in t.tolist():
            ab, bc, ca = (index[(min(u, v), max(u, v))] for u, v in ((a, b), (b, c), (c, a)))
            children += [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        t = np.array(children)
    return p, t


def edge_point_rows(plan, level=0):
    """{(a, b) with a < b: output row} for the edges of `level`, from the plan's documented output order."""
    first = plan.level_num_vertices(level)
    return {(min(a, b), max(a, b)): first + k for k, (a, b) in enumerate(plan.level_edges(level).tolist())}


def assert_same_point_sets(actual, expected, tol):
    """Every point of each set has a point of the other within `tol` (the two orders may differ)."""
    actual, expected = np.asarray(actual, np.float64), np.asarray(expected, np.float64)
    assert actual.shape == expected.shape
    d = np.linalg.norm(actual[:, None, :] - expected[None, :, :], axis=-1)
    assert d.min(axis=1).max() <= tol, f"an output point is {d.min(axis=1).max()} from every expected point"
    assert d.min(axis=0).max() <= tol, f"an expected point is {d.min(axis=0).max()} from every output point"


@pytest.fixture
def tetra():
    return tetrahedron()
