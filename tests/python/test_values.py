"""Refined values against masks derived by hand from RULES.md section 1 and OpenSubdiv's Sdc rules.

Every expected value is computed here, in float64, from the masks; none comes from the project's code. The plan's
documented output order (old vertices first, then one vertex per edge of `level_edges`) is used to find which
output row is which edge point, and that order is itself checked against the mesh's true edges.
"""
import math

import numpy as np
import pytest

import _loopsub
from conftest import (assert_same_point_sets, boundary_fan, edge_point_rows, edges_of, hexagon_disk, icosahedron,
                      loop_b, reference_loop_mesh, smooth_loop_reference, tetrahedron)

RULES = ["hoppe94", "opensubdiv"]
TOL = 2e-6  # float32 arithmetic on coordinates of size ~1


def refine(positions, triangles, levels=1, **options):
    plan = _loopsub.Plan(triangles, len(positions), levels, **options)
    return plan, plan.evaluate(positions).astype(np.float64)


def check_edge_order(plan, triangles):
    """level_edges(0) lists each edge of the input exactly once."""
    listed = [tuple(sorted(e)) for e in plan.level_edges(0).tolist()]
    assert len(listed) == len(set(listed))
    assert set(listed) == set(edges_of(triangles))


# ---------------------------------------------------------------------------------------------------------------
# Smooth meshes


@pytest.mark.parametrize("rules", RULES)
def test_tetrahedron_level1_smooth_masks(rules):
    p, t = tetrahedron()
    plan, out = refine(p, t, rules=rules)
    check_edge_order(plan, t)
    assert out.shape == (4 + 6, 3)

    # Valence 3: b(3) = (3 + 2 cos(2pi/3)) / 8 = 1/4, a(3) = 5/8 - 1/16 = 9/16.
    a3 = 5 / 8 - ((3 + 2 * math.cos(2 * math.pi / 3)) / 8) ** 2
    assert a3 == pytest.approx(9 / 16)
    P = p.astype(np.float64)
    for i in range(4):
        ring = [j for j in range(4) if j != i]
        expected = (1 - a3) * P[i] + a3 / 3 * P[ring].sum(0)
        # On a regular tetrahedron centred at 0 the ring sums to -v: 7/16 v - 3/16 v = v / 4.
        assert np.allclose(expected, P[i] / 4)
        np.testing.assert_allclose(out[i], expected, atol=TOL)

    rows = edge_point_rows(plan)
    for (a, b), row in rows.items():
        c, d = (j for j in range(4) if j not in (a, b))
        expected = 3 / 8 * (P[a] + P[b]) + 1 / 8 * (P[c] + P[d])
        assert np.allclose(expected, (P[a] + P[b]) / 4)
        np.testing.assert_allclose(out[row], expected, atol=TOL)


@pytest.mark.parametrize("rules", RULES)
def test_icosahedron_seed_worked_example(rules):
    """The seed's example: valence 5, a(5) = 0.4205, c0 = 5 / a(5) - 5 = 6.892, v0' = (c0 v0 + sum vi) / 11.892."""
    a5 = 5 / 8 - ((3 + 2 * math.cos(2 * math.pi / 5)) / 8) ** 2
    assert a5 == pytest.approx(0.4205, abs=5e-5)
    c0 = 5 / a5 - 5
    assert c0 == pytest.approx(6.892, abs=5e-4)

    p, t = icosahedron()
    plan, out = refine(p, t, rules=rules)
    check_edge_order(plan, t)
    P = p.astype(np.float64)
    rings = {i: set() for i in range(12)}
    for a, b in edges_of(t):
        rings[a].add(b)
        rings[b].add(a)
    for i, ring in rings.items():
        assert len(ring) == 5
        expected = (c0 * P[i] + P[sorted(ring)].sum(0)) / (c0 + 5)
        np.testing.assert_allclose(out[i], expected, atol=TOL)
    _, edge_points = smooth_loop_reference(p, t)
    for e, row in edge_point_rows(plan).items():
        np.testing.assert_allclose(out[row], edge_points[e], atol=TOL)


@pytest.mark.parametrize("rules", RULES)
def test_icosahedron_three_levels_match_reference(rules):
    """Several levels (topology of levels 1 and 2 included) against the hand-written reference, as point sets."""
    p, t = icosahedron()
    plan, out = refine(p, t, levels=3, rules=rules)
    expected, expected_triangles = reference_loop_mesh(p, t, 3)
    assert plan.num_output_triangles == len(expected_triangles) == 20 * 4**3
    assert_same_point_sets(out, expected, 1e-5)


# ---------------------------------------------------------------------------------------------------------------
# Creases, darts, corners, cones


@pytest.mark.parametrize("rules", RULES)
def test_crease_loop_on_tetrahedron(rules):
    """Face 0-1-2's edges tagged sharp: 0, 1, 2 are crease vertices, 3 stays smooth.

    Crease vertex: (6 v0 + v1 + v2) / 8. The crease edges join two irregular crease vertices (valence 3, not 6):
    Hoppe's {1,1,0,0} and OpenSubdiv's sharp edge both give the midpoint. Edges to vertex 3 are smooth.
    """
    p, t = tetrahedron()
    creases = np.array([[0, 1], [1, 2], [2, 0]], np.int32)
    plan, out = refine(p, t, rules=rules, crease_edges=creases)
    P = p.astype(np.float64)
    for i in range(3):
        j, k = (x for x in range(3) if x != i)
        np.testing.assert_allclose(out[i], (6 * P[i] + P[j] + P[k]) / 8, atol=TOL)
    np.testing.assert_allclose(out[3], 7 / 16 * P[3] + 3 / 16 * P[:3].sum(0), atol=TOL)
    rows = edge_point_rows(plan)
    for (a, b), row in rows.items():
        if b == 3:
            c, d = (x for x in range(4) if x not in (a, b))
            np.testing.assert_allclose(out[row], 3 / 8 * (P[a] + P[b]) + 1 / 8 * (P[c] + P[d]), atol=TOL)
        else:
            np.testing.assert_allclose(out[row], (P[a] + P[b]) / 2, atol=TOL)


def test_dart_edge_differs_between_rule_sets():
    """One sharp edge 0-1: both ends are darts (one crease edge each), which use the smooth vertex mask.

    Hoppe 94: a crease with a dart end is bisected with the smooth mask {3,3,1,1}, so nothing differs from the
    untagged mesh. OpenSubdiv: a sharp edge is always bisected at its midpoint (RULES.md section 3, point 2).
    """
    p, t = tetrahedron()
    crease = np.array([[0, 1]], np.int32)
    P = p.astype(np.float64)
    vertex_points, edge_points = smooth_loop_reference(p, t)

    plan, hoppe = refine(p, t, rules="hoppe94", crease_edges=crease)
    np.testing.assert_allclose(hoppe[:4], vertex_points, atol=TOL)
    for e, row in edge_point_rows(plan).items():
        np.testing.assert_allclose(hoppe[row], edge_points[e], atol=TOL)
    assert [_loopsub.VERTEX_TYPES[x] for x in plan.level_vertex_types(0)] == ["dart", "dart", "smooth", "smooth"]

    plan, osd = refine(p, t, rules="opensubdiv", crease_edges=crease)
    np.testing.assert_allclose(osd[:4], vertex_points, atol=TOL)
    for e, row in edge_point_rows(plan).items():
        expected = (P[0] + P[1]) / 2 if e == (0, 1) else edge_points[e]
        np.testing.assert_allclose(osd[row], expected, atol=TOL)


def test_semi_sharp_edge_blends_smooth_and_sharp():
    """OpenSubdiv, edge 0-1 of sharpness s in (0, 1): its point is s * midpoint + (1 - s) * smooth point.

    Its ends are darts before and smooth after the level, so their mask is the smooth one. Sharpness 1 (child
    sharpness 0, but the parent edge is a full crease) gives the midpoint.
    """
    p, t = tetrahedron()
    P = p.astype(np.float64)
    vertex_points, edge_points = smooth_loop_reference(p, t)
    for s in (0.25, 0.5, 1.0):
        plan, out = refine(p, t, rules="opensubdiv", crease_edges=np.array([[1, 0]], np.int32),
                           crease_sharpness=np.array([s], np.float32))
        np.testing.assert_allclose(out[:4], vertex_points, atol=TOL)
        row = edge_point_rows(plan)[(0, 1)]
        np.testing.assert_allclose(out[row], s * (P[0] + P[1]) / 2 + (1 - s) * edge_points[(0, 1)], atol=TOL)
        assert len(plan.crease_edges) == 0, "a sharpness <= 1 is used up after one level"


def test_semi_sharp_crease_vertex_transition():
    """OpenSubdiv, the crease loop 0-1-2 with sharpness 0.5: each crease vertex goes from the crease rule to the
    smooth rule, so its mask is the blend 0.5 * crease + 0.5 * smooth (Sdc's fractional weight: the mean
    sharpness of the edges that become smooth)."""
    p, t = tetrahedron()
    P = p.astype(np.float64)
    creases = np.array([[0, 1], [1, 2], [2, 0]], np.int32)
    plan, out = refine(p, t, rules="opensubdiv", crease_edges=creases,
                       crease_sharpness=np.full(3, 0.5, np.float32))
    vertex_points, edge_points = smooth_loop_reference(p, t)
    for i in range(3):
        j, k = (x for x in range(3) if x != i)
        crease = (6 * P[i] + P[j] + P[k]) / 8
        np.testing.assert_allclose(out[i], 0.5 * crease + 0.5 * vertex_points[i], atol=TOL)
    np.testing.assert_allclose(out[3], vertex_points[3], atol=TOL)
    for e, row in edge_point_rows(plan).items():
        expected = edge_points[e] if 3 in e else 0.5 * (P[e[0]] + P[e[1]]) / 2 + 0.5 * edge_points[e]
        np.testing.assert_allclose(out[row], expected, atol=TOL)


def test_crease_threshold_selects_hoppe_creases():
    """Hoppe 94: sharpness 0.5 on the loop 0-1-2 is a crease for thresholds 0 and 0.5, not for 0.6."""
    p, t = tetrahedron()
    P = p.astype(np.float64)
    options = dict(rules="hoppe94", crease_edges=np.array([[0, 1], [1, 2], [2, 0]], np.int32),
                   crease_sharpness=np.full(3, 0.5, np.float32))
    creased = (6 * P[0] + P[1] + P[2]) / 8
    smooth = smooth_loop_reference(p, t)[0][0]
    for threshold, expected in ((0.0, creased), (0.5, creased), (0.6, smooth)):
        _, out = refine(p, t, crease_threshold=threshold, **options)
        np.testing.assert_allclose(out[0], expected, atol=TOL, err_msg=f"threshold {threshold}")


@pytest.mark.parametrize("rules", RULES)
def test_infinitely_sharp_corner_stays(rules):
    p, t = tetrahedron()
    plan, out = refine(p, t, rules=rules, corner_vertices=np.array([0], np.int32))
    vertex_points, _ = smooth_loop_reference(p, t)
    np.testing.assert_allclose(out[0], p[0], atol=TOL)
    np.testing.assert_allclose(out[1:4], vertex_points[1:], atol=TOL)
    assert _loopsub.VERTEX_TYPES[plan.level_vertex_types(0)[0]] == "corner"


def test_semi_sharp_corner():
    """Corner sharpness 0.5: OpenSubdiv blends 0.5 * corner + 0.5 * smooth (= 0.625 v on the centred
    tetrahedron); Hoppe 94 makes any positive corner sharpness a corner."""
    p, t = tetrahedron()
    P = p.astype(np.float64)
    options = dict(corner_vertices=np.array([0], np.int32), corner_sharpness=np.array([0.5], np.float32))
    _, osd = refine(p, t, rules="opensubdiv", **options)
    np.testing.assert_allclose(osd[0], 0.5 * P[0] + 0.5 * (7 / 16 * P[0] + 3 / 16 * P[1:].sum(0)), atol=TOL)
    np.testing.assert_allclose(osd[0], 0.625 * P[0], atol=TOL)
    _, hoppe = refine(p, t, rules="hoppe94", **options)
    np.testing.assert_allclose(hoppe[0], P[0], atol=TOL)


def test_cone_vertex():
    """Hoppe 94 cone, valence 3: c0 = n / (5/8 - b(n)) - n = 3 / (3/8) - 3 = 5, so v0' = (5 v0 + v1 + v2 + v3) / 8
    (centre weight 3/8 + b(3) = 0.625 as in RULES.md)."""
    p, t = tetrahedron()
    P = p.astype(np.float64)
    c0 = 3 / (5 / 8 - loop_b(3)) - 3
    assert c0 == pytest.approx(5)
    plan, out = refine(p, t, rules="hoppe94", cone_vertices=np.array([0], np.int32))
    np.testing.assert_allclose(out[0], (c0 * P[0] + P[1:].sum(0)) / (c0 + 3), atol=TOL)
    np.testing.assert_allclose(out[0], P[0] / 2, atol=TOL)
    vertex_points, edge_points = smooth_loop_reference(p, t)
    np.testing.assert_allclose(out[1:4], vertex_points[1:], atol=TOL)
    for e, row in edge_point_rows(plan).items():
        np.testing.assert_allclose(out[row], edge_points[e], atol=TOL)
    assert _loopsub.VERTEX_TYPES[plan.level_vertex_types(0)[0]] == "cone"


def test_cones_are_ignored_under_opensubdiv_rules():
    """OpenSubdiv has no cones (RULES.md section 3): the tag changes nothing there, as documented."""
    p, t = tetrahedron()
    _, tagged = refine(p, t, rules="opensubdiv", cone_vertices=np.array([0], np.int32))
    np.testing.assert_allclose(tagged[:4], smooth_loop_reference(p, t)[0], atol=TOL)


# ---------------------------------------------------------------------------------------------------------------
# Boundaries and the {5,3} rule


@pytest.mark.parametrize("rules,boundary", [("hoppe94", "edges"), ("opensubdiv", "edges")])
def test_single_triangle_boundary_creases(rules, boundary):
    """Every edge is a boundary edge, hence a crease: vertices (6 v0 + v1 + v2) / 8, edges at their midpoints."""
    p = np.array([[0, 0, 0], [2, 0, 0.5], [0.3, 1.7, -0.2]], np.float32)
    t = np.array([[0, 1, 2]], np.int32)
    plan, out = refine(p, t, rules=rules, boundary=boundary)
    P = p.astype(np.float64)
    for i in range(3):
        j, k = (x for x in range(3) if x != i)
        np.testing.assert_allclose(out[i], (6 * P[i] + P[j] + P[k]) / 8, atol=TOL)
    for (a, b), row in edge_point_rows(plan).items():
        np.testing.assert_allclose(out[row], (P[a] + P[b]) / 2, atol=TOL)


def test_single_triangle_edges_and_corners_keeps_corners():
    """OpenSubdiv's VTX_BOUNDARY_EDGE_AND_CORNER: a boundary vertex with one face is a corner and stays put."""
    p = np.array([[0, 0, 0], [2, 0, 0.5], [0.3, 1.7, -0.2]], np.float32)
    t = np.array([[0, 1, 2]], np.int32)
    plan, out = refine(p, t, rules="opensubdiv", boundary="edges-and-corners")
    np.testing.assert_allclose(out[:3], p, atol=TOL)
    P = p.astype(np.float64)
    for (a, b), row in edge_point_rows(plan).items():
        np.testing.assert_allclose(out[row], (P[a] + P[b]) / 2, atol=TOL)


def test_regular_boundary_crease_vertex_and_53_rule():
    """Hoppe 94 on a half fan: vertex 0 is a regular boundary crease vertex (valence 4, three faces), vertices 1
    and 4 irregular ones (valence 2). Boundary edge 0-1 joins regular and irregular: {5,3,0,0} with the 5 on
    vertex 0. Edge 1-2 joins two irregular ones: midpoint. OpenSubdiv bisects every sharp edge at its midpoint."""
    p, t = boundary_fan()
    P = p.astype(np.float64)
    plan, hoppe = refine(p, t, rules="hoppe94")
    types = [_loopsub.VERTEX_TYPES[x] for x in plan.level_vertex_types(0)]
    assert types == ["regular_crease"] + ["irregular_crease"] * 4
    rows = edge_point_rows(plan)
    np.testing.assert_allclose(hoppe[rows[(0, 1)]], (5 * P[0] + 3 * P[1]) / 8, atol=TOL)
    np.testing.assert_allclose(hoppe[rows[(0, 4)]], (5 * P[0] + 3 * P[4]) / 8, atol=TOL)
    np.testing.assert_allclose(hoppe[rows[(1, 2)]], (P[1] + P[2]) / 2, atol=TOL)
    np.testing.assert_allclose(hoppe[rows[(0, 2)]], 3 / 8 * (P[0] + P[2]) + 1 / 8 * (P[1] + P[3]), atol=TOL)
    np.testing.assert_allclose(hoppe[0], (6 * P[0] + P[1] + P[4]) / 8, atol=TOL)
    np.testing.assert_allclose(hoppe[2], (6 * P[2] + P[1] + P[3]) / 8, atol=TOL)

    plan, osd = refine(p, t, rules="opensubdiv")
    rows = edge_point_rows(plan)
    np.testing.assert_allclose(osd[rows[(0, 1)]], (P[0] + P[1]) / 2, atol=TOL)
    np.testing.assert_allclose(osd[0], (6 * P[0] + P[1] + P[4]) / 8, atol=TOL)


def test_interior_regular_crease_and_53_rule():
    """Hoppe 94 on a hexagonal disk creased along 1-0-4: the centre (valence 6, three faces each side) is a
    regular crease vertex; rim vertices 1 and 4 have three crease edges (two boundary, one tagged): corners.
    Crease edge 0-1 joins regular and corner: (5 v0 + 3 v1) / 8."""
    p, t = hexagon_disk()
    P = p.astype(np.float64)
    creases = np.array([[0, 1], [4, 0]], np.int32)
    plan, hoppe = refine(p, t, rules="hoppe94", crease_edges=creases)
    types = [_loopsub.VERTEX_TYPES[x] for x in plan.level_vertex_types(0)]
    assert types == ["regular_crease", "corner", "irregular_crease", "irregular_crease", "corner",
                     "irregular_crease", "irregular_crease"]
    rows = edge_point_rows(plan)
    np.testing.assert_allclose(hoppe[rows[(0, 1)]], (5 * P[0] + 3 * P[1]) / 8, atol=TOL)
    np.testing.assert_allclose(hoppe[rows[(0, 4)]], (5 * P[0] + 3 * P[4]) / 8, atol=TOL)
    np.testing.assert_allclose(hoppe[0], (6 * P[0] + P[1] + P[4]) / 8, atol=TOL)
    np.testing.assert_allclose(hoppe[1], P[1], atol=TOL)
    # A smooth interior edge 0-2, opposite vertices 1 and 3.
    np.testing.assert_allclose(hoppe[rows[(0, 2)]], 3 / 8 * (P[0] + P[2]) + 1 / 8 * (P[1] + P[3]), atol=TOL)

    plan, osd = refine(p, t, rules="opensubdiv", crease_edges=creases)
    rows = edge_point_rows(plan)
    np.testing.assert_allclose(osd[rows[(0, 1)]], (P[0] + P[1]) / 2, atol=TOL)
    np.testing.assert_allclose(osd[1], P[1], atol=TOL)  # three sharp edges: a corner in Sdc too


def test_interior_irregular_crease_uses_midpoint():
    """Creased along 1-0-3 instead: two faces on one side, four on the other, so the centre is an irregular
    crease vertex and crease edge 0-1 (irregular to corner) gets the midpoint."""
    p, t = hexagon_disk()
    P = p.astype(np.float64)
    plan, out = refine(p, t, rules="hoppe94", crease_edges=np.array([[0, 1], [0, 3]], np.int32))
    assert _loopsub.VERTEX_TYPES[plan.level_vertex_types(0)[0]] == "irregular_crease"
    rows = edge_point_rows(plan)
    np.testing.assert_allclose(out[rows[(0, 1)]], (P[0] + P[1]) / 2, atol=TOL)
    np.testing.assert_allclose(out[0], (6 * P[0] + P[1] + P[3]) / 8, atol=TOL)


# ---------------------------------------------------------------------------------------------------------------
# Output tags, fed back in


def test_output_crease_tags_are_halves_with_decremented_sharpness():
    p, t = tetrahedron()
    creases = np.array([[0, 1], [1, 2], [2, 0]], np.int32)
    plan = _loopsub.Plan(t, 4, 1, rules="opensubdiv", crease_edges=creases,
                         crease_sharpness=np.array([2.5, 10, 1.5], np.float32),
                         corner_vertices=np.array([3], np.int32))
    mid = edge_point_rows(plan)
    expected = {}
    for (a, b), s in (((0, 1), 1.5), ((1, 2), 10.0), ((0, 2), 0.5)):
        for end in (a, b):
            expected[tuple(sorted((end, mid[(a, b)])))] = s
    got = {tuple(sorted(e)): s for e, s in zip(plan.crease_edges.tolist(), plan.crease_sharpness.tolist())}
    assert got == pytest.approx(expected)
    assert plan.corner_vertices.tolist() == [3]
    assert plan.corner_sharpness.tolist() == [10.0]


@pytest.mark.parametrize("rules", RULES)
def test_result_fed_back_in_equals_two_levels(rules):
    """Subdividing the level-1 result (with its output tags) once more gives the level-2 result."""
    p, t = hexagon_disk()
    options = dict(rules=rules, crease_edges=np.array([[0, 1], [0, 4], [0, 2]], np.int32),
                   crease_sharpness=np.array([10, 2.5, 1.5], np.float32), corner_vertices=np.array([5], np.int32))
    once = _loopsub.subdivide(p, t, 1, **options)
    again = _loopsub.subdivide(once["positions"], np.ascontiguousarray(once["triangles"]), 1, rules=rules,
                               crease_edges=once["crease_edges"], crease_sharpness=once["crease_sharpness"],
                               corner_vertices=once["corner_vertices"], corner_sharpness=once["corner_sharpness"])
    twice = _loopsub.subdivide(p, t, 2, **options)
    assert len(again["triangles"]) == len(twice["triangles"]) == 6 * 16
    assert_same_point_sets(again["positions"], twice["positions"], 1e-6)


# ---------------------------------------------------------------------------------------------------------------
# Other per-vertex channels and face-varying data


@pytest.mark.parametrize("rules", RULES)
def test_vertex_data_uses_the_position_weights(rules):
    """Channels equal to z, x, y come out equal to the refined z, x, y; a constant channel stays constant (every
    mask sums to one)."""
    p, t = hexagon_disk()
    data = np.ascontiguousarray(np.column_stack([p[:, 2], p[:, 0], p[:, 1], np.full(len(p), 0.75, np.float32)]))
    r = _loopsub.subdivide(p, t, 3, rules=rules, crease_edges=np.array([[0, 1], [0, 4]], np.int32),
                           crease_sharpness=np.array([10, 1.5], np.float32), vertex_data=data)
    out = r["vertex_data"]
    assert out.shape == (len(r["positions"]), 4) and out.dtype == np.float32
    np.testing.assert_allclose(out[:, :3], r["positions"][:, [2, 0, 1]], atol=1e-6)
    np.testing.assert_allclose(out[:, 3], 0.75, atol=1e-6)
    # Not trivially equal to the input: the channels did move.
    assert np.abs(out[: len(p), 1] - p[:, 0]).max() > 1e-3


def test_vertex_data_dict_and_single_channel():
    p, t = tetrahedron()
    data = {"x": np.ascontiguousarray(p[:, 0]), "one": np.ones((4, 1), np.float32)}
    r = _loopsub.subdivide(p, t, 2, vertex_data=data)
    assert set(r["vertex_data"]) == {"x", "one"}
    assert r["vertex_data"]["x"].shape == (len(r["positions"]),)
    np.testing.assert_allclose(r["vertex_data"]["x"], r["positions"][:, 0], atol=1e-6)
    np.testing.assert_allclose(r["vertex_data"]["one"], 1.0, atol=1e-6)


def linear_positions(plan, positions):
    """Each output vertex's position by linear interpolation only: old vertices stay, edge vertices are midpoints
    (recursively through the levels), i.e. the control cage's flat surface."""
    lin = np.asarray(positions, np.float64)
    for level in range(plan.levels):
        e = plan.level_edges(level)
        lin = np.vstack([lin, (lin[e[:, 0]] + lin[e[:, 1]]) / 2])
    return lin


@pytest.mark.parametrize("rules", RULES)
def test_face_varying_is_linear_per_face_and_keeps_seams(rules):
    """A UV equal to the corner's (x, y, z) plus an offset per face (every edge is a seam) must come out as the
    linear interpolation within the parent face: linear position of the output vertex + its parent's offset."""
    p, t = icosahedron()
    levels = 2
    offsets = 10.0 * np.arange(len(t), dtype=np.float64)
    uv = (p[t].astype(np.float64) + offsets[:, None, None]).astype(np.float32)
    plan = _loopsub.Plan(t, len(p), levels, rules=rules)
    out = plan.evaluate_face_varying(uv)
    assert out.shape == (len(t) * 4**levels, 3, 3) and out.dtype == np.float32
    lin = linear_positions(plan, p)
    expected = lin[plan.triangles] + offsets[plan.parent_triangles][:, None, None]
    np.testing.assert_allclose(out, expected, atol=1e-4)
    # The smoothed positions differ from the linear ones: a smoothed UV would fail the check above.
    assert np.abs(plan.evaluate(p)[plan.triangles] - lin[plan.triangles]).max() > 0.05


def test_face_varying_single_channel_and_subdivide_dict():
    p, t = tetrahedron()
    u = np.ascontiguousarray(p[t][:, :, 0])  # (T, 3): one channel
    r = _loopsub.subdivide(p, t, 1, face_varying={"u": u, "uvw": np.ascontiguousarray(p[t])}, uv_interpolation="all")
    plan = r["plan"]
    lin = linear_positions(plan, p)
    assert r["face_varying"]["u"].shape == (16, 3)
    np.testing.assert_allclose(r["face_varying"]["u"], lin[plan.triangles][:, :, 0], atol=1e-6)
    np.testing.assert_allclose(r["face_varying"]["uvw"], lin[plan.triangles], atol=1e-6)


@pytest.mark.parametrize("rules", RULES)
@pytest.mark.parametrize("mode", ["none", "corners", "corners-plus1", "corners-plus2", "boundaries"])
def test_face_varying_without_seams_follows_the_vertices(rules, mode):
    # Every corner of a vertex carries the vertex's own value: no seam anywhere, so in every smooth mode a
    # face-varying layer refines exactly as vertex data does (on a closed mesh, where boundaries play no part).
    p, t = tetrahedron()
    r = _loopsub.subdivide(p, t, 2, rules=rules, face_varying=np.ascontiguousarray(p[t]), uv_interpolation=mode)
    np.testing.assert_allclose(r["face_varying"], r["positions"][r["triangles"]], atol=1e-6)


# ---------------------------------------------------------------------------------------------------------------
# Re-evaluation, kernels, threads


@pytest.mark.parametrize("rules", RULES)
def test_plan_reevaluated_equals_fresh_subdivide(rules):
    p, t = hexagon_disk()
    options = dict(rules=rules, crease_edges=np.array([[0, 1], [0, 4]], np.int32),
                   crease_sharpness=np.array([10, 1.5], np.float32))
    plan = _loopsub.Plan(t, len(p), 3, **options)
    first = plan.evaluate(p)
    moved = (p * np.float32(1.7) + np.random.default_rng(1).uniform(-0.2, 0.2, p.shape)).astype(np.float32)
    again = plan.evaluate(moved)
    fresh = _loopsub.subdivide(moved, t, 3, **options)
    np.testing.assert_array_equal(again, fresh["positions"])
    np.testing.assert_array_equal(plan.triangles, fresh["triangles"])
    assert not np.allclose(first, again)
    np.testing.assert_array_equal(plan.evaluate(p), first)


@pytest.mark.parametrize("rules", RULES)
@pytest.mark.parametrize("channels", [1, 2, 3, 4, 5, 8, 13])
def test_scalar_and_simd_and_threads_agree(rules, channels):
    """The SIMD kernels (several layouts depending on the channel count) and the two-thread split (used from a
    few thousand outputs per level on, hence level 5) give the scalar reference kernel's values."""
    p, t = icosahedron()
    values = np.ascontiguousarray(np.tile(p, 5)[:, :channels] * np.linspace(1, 2, channels, dtype=np.float32))
    creases = dict(crease_edges=np.array([[0, 11], [11, 5]], np.int32),
                   crease_sharpness=np.array([10, 1.5], np.float32))
    scalar_plan = _loopsub.Plan(t, len(p), 5, rules=rules, scalar=True, **creases)
    assert scalar_plan.kernel == "scalar"
    reference = scalar_plan.evaluate(values)
    for options in (dict(), dict(threads=2), dict(threads=2, scalar=True)):
        plan = _loopsub.Plan(t, len(p), 5, rules=rules, **options, **creases)
        assert plan.kernel == ("scalar" if options.get("scalar") else _loopsub.best_kernel())
        np.testing.assert_allclose(plan.evaluate(values), reference, atol=2e-6, err_msg=str(options))


def _evaluate_in_child(levels):
    p, t = icosahedron()
    return _loopsub.Plan(t, len(p), levels, threads=2).evaluate(p)


def test_two_threads_in_a_forked_child():
    """A pipeline that evaluates on two threads, then forks workers (multiprocessing's default on Linux): the module
    keeps its threads between calls, and a child has none of its parent's threads, so it must make its own rather than
    wait forever for them. The children's results equal the parent's."""
    import multiprocessing

    p, t = icosahedron()
    expected = _loopsub.Plan(t, len(p), 5, threads=2).evaluate(p)  # the parent's kept threads exist from here
    with multiprocessing.get_context("fork").Pool(2) as pool:
        results = pool.map_async(_evaluate_in_child, [5, 5, 5]).get(timeout=120)
    for result in results:
        np.testing.assert_array_equal(result, expected)


# ---------------------------------------------------------------------------------------------------------------
# The limit surface, face-varying layers, holes


@pytest.mark.parametrize("rules", RULES)
def test_limit_normals_are_unit_and_point_out_of_a_closed_mesh(rules):
    p, t = tetrahedron()
    plan = _loopsub.Plan(t, len(p), 2, rules=rules, limit_surface=True)
    positions, normals = plan.evaluate_with_normals(p)
    assert positions.shape == (plan.num_output_vertices, 3)
    assert normals.shape == (plan.num_output_triangles, 3, 3)
    np.testing.assert_allclose(np.linalg.norm(normals, axis=2), 1.0, atol=1e-5)
    # The tetrahedron is centred on the origin: outward normals point away from it.
    assert (np.einsum("tkc,tkc->tk", normals, positions[plan.triangles]) > 0).all()
    # The same plan without normals gives the same limit positions.
    np.testing.assert_array_equal(plan.evaluate(p), positions)


def test_normals_need_the_limit_surface():
    p, t = tetrahedron()
    with pytest.raises(ValueError, match="limit_surface=True"):
        _loopsub.Plan(t, len(p), 1).evaluate_with_normals(p)
    with pytest.raises(ValueError, match="at least 3 channels"):
        _loopsub.Plan(t, len(p), 1, limit_surface=True).evaluate_with_normals(np.ascontiguousarray(p[:, :2]))


@pytest.mark.parametrize("rules", RULES)
def test_compact_limit_normals_gathered_are_the_corner_normals(rules):
    p, t = tetrahedron()
    creases = np.array([[int(t[0, 0]), int(t[0, 1])]], np.int32)
    plan = _loopsub.Plan(t, len(p), 2, rules=rules, limit_surface=True, crease_edges=creases)
    positions, corner_normals = plan.evaluate_with_normals(p)
    compact_positions, normals = plan.evaluate_with_limit_normals(p)
    np.testing.assert_array_equal(compact_positions, positions)
    assert normals.shape == (plan.num_limit_normals, 3)
    assert plan.num_limit_normals > plan.num_output_vertices  # the crease's vertices have sides
    indices = plan.corner_normal_indices
    assert indices.shape == (plan.num_output_triangles, 3) and indices.dtype == np.int32 and not indices.flags.writeable
    assert ((indices == plan.triangles) | (indices >= plan.num_output_vertices)).all()
    np.testing.assert_array_equal(normals[indices], corner_normals)
    # Into given arrays.
    out = np.empty_like(positions)
    given = np.empty_like(normals)
    result = plan.evaluate_with_limit_normals(p, out=out, normals=given)
    assert result[0] is out and result[1] is given
    np.testing.assert_array_equal(given, normals)


def test_compact_limit_normals_need_the_limit_surface():
    p, t = tetrahedron()
    plan = _loopsub.Plan(t, len(p), 1)
    for call in (lambda: plan.evaluate_with_limit_normals(p), lambda: plan.corner_normal_indices,
                 lambda: plan.num_limit_normals):
        with pytest.raises(ValueError, match="limit_surface=True"):
            call()
    limit_plan = _loopsub.Plan(t, len(p), 1, limit_surface=True)
    with pytest.raises(ValueError, match="at least 3 channels"):
        limit_plan.evaluate_with_limit_normals(np.ascontiguousarray(p[:, :2]))
    with pytest.raises(ValueError):
        limit_plan.evaluate_with_limit_normals(p, normals=np.empty((limit_plan.num_limit_normals + 1, 3), np.float32))


def test_face_varying_layer_by_indices_equals_the_welded_corners():
    p, t = tetrahedron()
    # A seam: triangle 0 has its own copies of its three values.
    indices = np.array([[4, 5, 6], [0, 2, 3], [0, 3, 1], [1, 3, 2]], np.int32)
    values = np.array([[0, 0], [1, 0], [0, 1], [1, 1], [2, 2], [3, 2], [2, 3]], np.float32)
    plan = _loopsub.Plan(t, len(p), 2, rules="opensubdiv", face_varying_indices=[indices],
                         uv_interpolation="boundaries")
    assert plan.num_face_varying_layers == 1
    refined = plan.evaluate_face_varying(values, layer=0)
    per_corner = refined[plan.face_varying_indices(0)]
    r = _loopsub.subdivide(p, t, 2, rules="opensubdiv", face_varying=np.ascontiguousarray(values[indices]),
                           uv_interpolation="boundaries")
    np.testing.assert_array_equal(per_corner, r["face_varying"])
    # Keep Boundaries: the seam's corners stay where they were.
    for corner in range(3):
        assert any(np.array_equal(values[4 + corner], uv) for uv in per_corner.reshape(-1, 2))
    with pytest.raises(ValueError, match="layer 1"):
        plan.evaluate_face_varying(values, layer=1)
    with pytest.raises(ValueError, match=r"\(N=7, C\)"):
        plan.evaluate_face_varying(values[:6], layer=0)


def test_holes_are_left_out_and_refuse_bad_indices():
    p, t = tetrahedron()
    r = _loopsub.subdivide(p, t, 2, hole_triangles=np.array([1], np.int32))
    assert r["triangles"].shape == (3 * 16, 3)
    assert set(r["parent_triangles"].tolist()) == {0, 2, 3}
    assert r["positions"].shape[0] == _loopsub.subdivide(p, t, 2)["positions"].shape[0]  # vertices stay
    with pytest.raises(ValueError, match="hole 0 refers to triangle 4"):
        _loopsub.Plan(t, len(p), 1, hole_triangles=np.array([4], np.int32))
