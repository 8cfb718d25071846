"""Shapes, dtypes, properties, output order and zero-copy behaviour of the `_loopsub` module."""
import gc

import numpy as np
import pytest

import _loopsub
from conftest import edges_of, grid, icosahedron, tetrahedron


@pytest.mark.parametrize("levels", [0, 1, 2, 3])
def test_counts_shapes_and_dtypes(levels):
    """Closed mesh: F' = 4F, E' = 2E + 3F, V' = V + E at every level (hand-derived, not from the code)."""
    p, t = icosahedron()
    plan = _loopsub.Plan(t, len(p), levels)
    v, e, f = 12, 30, 20
    for level in range(levels):
        assert plan.level_num_vertices(level) == v
        assert plan.level_edges(level).shape == (e, 2)
        assert plan.level_vertex_types(level).shape == (v,)
        v, e, f = v + e, 2 * e + 3 * f, 4 * f
    assert plan.level_num_vertices(levels) == v
    assert (plan.levels, plan.num_input_vertices, plan.num_input_triangles) == (levels, 12, 20)
    assert (plan.num_output_vertices, plan.num_output_triangles) == (v, f)

    out = plan.evaluate(p)
    assert out.shape == (v, 3) and out.dtype == np.float32 and out.flags.c_contiguous
    for name, shape, dtype in [("triangles", (f, 3), np.int32), ("parent_triangles", (f,), np.int32)]:
        a = getattr(plan, name)
        assert a.shape == shape and a.dtype == dtype, name
    assert plan.evaluate(np.ascontiguousarray(p[:, 0])).shape == (v,)
    assert plan.evaluate(np.zeros((12, 5), np.float32)).shape == (v, 5)
    assert plan.evaluate_face_varying(np.zeros((20, 3, 2), np.float32)).shape == (f, 3, 2)
    assert plan.evaluate_face_varying(np.zeros((20, 3), np.float32)).shape == (f, 3)


def test_level_zero_is_the_input():
    p, t = tetrahedron()
    r = _loopsub.subdivide(p, t, 0)
    np.testing.assert_array_equal(r["positions"], p)
    np.testing.assert_array_equal(r["triangles"], t)
    np.testing.assert_array_equal(r["parent_triangles"], np.arange(4))


def test_parent_triangles_and_child_order():
    """Child 4f + k of a level has parent f, so after L levels triangle i comes from input triangle i // 4**L.
    The three corner children come first in the parent's corner order: child k holds parent corner k."""
    p, t = icosahedron()
    plan = _loopsub.Plan(t, len(p), 2)
    np.testing.assert_array_equal(plan.parent_triangles, np.arange(20 * 16) // 16)
    one = _loopsub.Plan(t, len(p), 1)
    children = one.triangles.reshape(20, 4, 3)
    for f in range(20):
        for k in range(3):
            assert t[f, k] in children[f, k], (f, k)
        assert (children[f, 3] >= 12).all(), "the middle child has only edge vertices"


def test_winding_is_kept():
    """Every output triangle's normal points the same way as its parent's (outward on the icosahedron)."""
    p, t = icosahedron()
    r = _loopsub.subdivide(p, t, 2)
    q, tt = r["positions"].astype(np.float64), r["triangles"]
    normals = np.cross(q[tt[:, 1]] - q[tt[:, 0]], q[tt[:, 2]] - q[tt[:, 0]])
    assert (np.einsum("ij,ij->i", normals, q[tt].mean(1)) > 0).all()
    # Each undirected edge is shared by exactly two triangles, in opposite directions: still a closed manifold.
    directed = {(a, b) for a, b, c in tt.tolist() for a, b in ((a, b), (b, c), (c, a))}
    assert len(directed) == 3 * len(tt)
    assert all((b, a) in directed for a, b in directed)


def test_subdivide_result_keys_and_plan():
    p, t = tetrahedron()
    r = _loopsub.subdivide(p, t, 1)
    assert set(r) == {"positions", "triangles", "parent_triangles", "crease_edges", "crease_sharpness",
                      "corner_vertices", "corner_sharpness", "vertex_data", "face_varying", "plan"}
    assert r["vertex_data"] is None and r["face_varying"] is None
    assert r["crease_edges"].shape == (0, 2) and r["crease_edges"].dtype == np.int32
    assert r["crease_sharpness"].shape == (0,) and r["crease_sharpness"].dtype == np.float32
    assert r["corner_vertices"].dtype == np.int32 and r["corner_sharpness"].dtype == np.float32
    assert isinstance(r["plan"], _loopsub.Plan)
    np.testing.assert_array_equal(r["plan"].evaluate(p), r["positions"])


def test_properties_and_repr():
    p, t = icosahedron()
    plan = _loopsub.Plan(t, len(p), 2, rules="opensubdiv", scalar=True)
    assert plan.rules == "opensubdiv"
    assert plan.kernel == "scalar"
    assert _loopsub.best_kernel() in ("scalar", "sse4.1", "avx2")
    assert plan.topology_ms >= 0
    plan.evaluate(p)
    assert plan.last_evaluate_ms >= 0
    assert "levels=2" in repr(plan)
    assert _loopsub.VERTEX_TYPES[0] == "smooth" and len(_loopsub.VERTEX_TYPES) == 6
    assert "Parameters" in _loopsub.Plan.__doc__ and "Returns" in _loopsub.subdivide.__doc__


def test_level_accessors_reject_bad_levels():
    p, t = tetrahedron()
    plan = _loopsub.Plan(t, 4, 2)
    for bad in (-1, 2):
        with pytest.raises(IndexError):
            plan.level_edges(bad)
    for bad in (-1, 3):
        with pytest.raises(IndexError):
            plan.level_vertex_types(bad)
    with pytest.raises(IndexError):
        plan.level_num_vertices(3)
    # The last level's classes: the output's, as a deeper plan repositions them.
    assert plan.level_vertex_types(2).shape == (plan.num_output_vertices,)
    np.testing.assert_array_equal(plan.level_vertex_types(2), _loopsub.Plan(t, 4, 3).level_vertex_types(2))
    assert set(map(tuple, np.sort(plan.level_edges(0), axis=1).tolist())) == set(edges_of(t))


def test_empty_mesh_gives_empty_result():
    for levels in (0, 1, 3):
        r = _loopsub.subdivide(np.zeros((0, 3), np.float32), np.zeros((0, 3), np.int32), levels,
                               vertex_data=np.zeros((0, 2), np.float32), face_varying=np.zeros((0, 3, 2), np.float32))
        assert r["positions"].shape == (0, 3) and r["positions"].dtype == np.float32
        assert r["triangles"].shape == (0, 3) and r["parent_triangles"].shape == (0,)
        assert r["vertex_data"].shape == (0, 2) and r["face_varying"].shape == (0, 3, 2)
        assert r["crease_edges"].shape == (0, 2)


def test_loose_vertex_is_kept():
    """A vertex in no triangle (Blender meshes have them) keeps its index and position."""
    p, t = tetrahedron()
    p5 = np.vstack([p, [[5, 6, 7]]]).astype(np.float32)
    r = _loopsub.subdivide(p5, t, 2)
    np.testing.assert_array_equal(r["positions"][4], [5, 6, 7])
    assert not (r["triangles"] == 4).any()


# ---------------------------------------------------------------------------------------------------------------
# Zero copy


def test_out_is_written_in_place():
    p, t = grid(5)
    plan = _loopsub.Plan(t, len(p), 2)
    out = np.full((plan.num_output_vertices, 3), np.nan, np.float32)
    result = plan.evaluate(p, out=out)
    assert result is out
    assert np.shares_memory(result, out)
    assert np.isfinite(out).all()
    np.testing.assert_array_equal(out, plan.evaluate(p))

    fv_out = np.full((plan.num_output_triangles, 3, 2), np.nan, np.float32)
    fv = plan.evaluate_face_varying(np.ones((len(t), 3, 2), np.float32), out=fv_out)
    assert fv is fv_out and (fv_out == 1).all()


def test_out_may_be_a_view_into_a_bigger_buffer():
    """A C-contiguous slice of rows of a preallocated buffer is a valid `out` (Blender's foreach_set buffers)."""
    p, t = tetrahedron()
    plan = _loopsub.Plan(t, 4, 1)
    buffer = np.zeros((plan.num_output_vertices + 2, 3), np.float32)
    plan.evaluate(p, out=buffer[1:-1])
    np.testing.assert_array_equal(buffer[1:-1], plan.evaluate(p))
    assert (buffer[0] == 0).all() and (buffer[-1] == 0).all()


def test_views_share_the_plans_memory_and_are_read_only():
    p, t = icosahedron()
    plan = _loopsub.Plan(t, len(p), 1, crease_edges=np.array([[0, 1]], np.int32))
    for get in (lambda: plan.triangles, lambda: plan.parent_triangles, lambda: plan.crease_edges,
                lambda: plan.crease_sharpness, lambda: plan.level_edges(0), lambda: plan.level_vertex_types(0)):
        a, b = get(), get()
        assert a.size > 0
        assert np.shares_memory(a, b), "two reads must be views of the same memory, not copies"
        assert not a.flags.writeable
        with pytest.raises(ValueError):
            a[0] = 0
        assert a.base is plan


def test_views_keep_the_plan_alive():
    p, t = icosahedron()
    plan = _loopsub.Plan(t, len(p), 3)
    triangles, edges = plan.triangles, plan.level_edges(2)
    expected_triangles, expected_edges = triangles.copy(), edges.copy()
    del plan
    gc.collect()
    # The arrays' base is still the plan, which must still be a working object...
    assert isinstance(triangles.base, _loopsub.Plan)
    assert triangles.base.num_output_triangles == len(triangles)
    # ...and memory churn does not change what the views show.
    junk = [np.full(len(expected_triangles) * 3, -7, np.int32) for _ in range(20)]
    del junk
    np.testing.assert_array_equal(triangles, expected_triangles)
    np.testing.assert_array_equal(edges, expected_edges)


def test_subdivide_arrays_outlive_the_call():
    p, t = icosahedron()
    r = _loopsub.subdivide(p, t, 2)
    triangles = r["triangles"]
    del r
    gc.collect()
    assert isinstance(triangles.base, _loopsub.Plan)
    assert triangles.max() < triangles.base.num_output_vertices


def test_new_results_are_plain_arrays_that_own_their_memory():
    """Results without `out` are in the core's memory (huge pages, reused when freed): each must still be an ordinary
    C-contiguous, writeable array of its own, valid after its plan and the next results are gone, and freed memory
    must go back (many results made and dropped do not grow the process)."""
    import resource
    p, t = grid(40, seed=3)
    uvs = np.stack([p[:, 0], p[:, 1]], 1).astype(np.float32)
    plan = _loopsub.Plan(t, len(p), 3, limit_surface=True, face_varying_indices=[t])
    results = [plan.evaluate(p), plan.evaluate_with_normals(p)[1], plan.evaluate_with_limit_normals(p)[1],
               plan.evaluate_face_varying(uvs, layer=0), plan.output_edges()[0]]
    expected = [r.copy() for r in results]
    for r in results:
        assert r.flags.c_contiguous and r.flags.writeable and r.flags.aligned
        assert r.strides[-1] == r.itemsize and r.strides[0] == r.itemsize * int(np.prod(r.shape[1:]))
        assert sum(np.shares_memory(r, other) for other in results) == 1
    del plan
    gc.collect()
    churn = [_loopsub.Plan(t, len(p), 3).evaluate(p) for _ in range(10)]
    del churn
    for r, e in zip(results, expected):
        np.testing.assert_array_equal(r, e)
    results[0][:] = 1.0  # writeable
    assert (results[0] == 1.0).all()
    big = _loopsub.Plan(t, len(p), 5)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    for _ in range(40):
        big.evaluate(p)  # 18.7 MB each, dropped at once
    assert resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before < 100 * 1024  # kB: not 40 results kept


def test_module_docstring_example_runs():
    import doctest
    result = doctest.testmod(_loopsub)
    assert result.attempted > 0 and result.failed == 0


def test_derived_level_tables_give_the_stored_result():
    # Pipelines choose how a plan keeps its tables; the result must not depend on it.
    positions, triangles = grid(12, seed=3, height=0.2)
    creases = np.array(sorted(edges_of(triangles))[:20], np.int32)
    results = {}
    for tables in ("stored", "derived", "auto"):
        plan = _loopsub.Plan(triangles, len(positions), levels=3, rules="opensubdiv", crease_edges=creases,
                             crease_sharpness=np.full(len(creases), 1.5, np.float32), level_tables=tables, threads=2)
        assert plan.level_tables == tables
        results[tables] = (plan.evaluate(positions), np.array(plan.triangles), np.array(plan.level_edges(2)))
    for stored, derived in zip(results["stored"], results["derived"]):
        np.testing.assert_array_equal(stored, derived)
    with pytest.raises(ValueError, match="level_tables must be 'auto', 'stored' or 'derived'"):
        _loopsub.Plan(triangles, len(positions), levels=2, level_tables="lean")


@pytest.mark.parametrize("levels", [1, 2, 3])
def test_output_edges_number_every_output_edge_once(levels):
    # A closed octahedron and an open strip: every triangle edge i joins corners i and i + 1, every edge is used,
    # none twice, the counts obey Euler's formula (V - E + F = 2 on the closed one), and the halves of edge e of the
    # level before are 2e and 2e + 1 (the numbering the API promises).
    for triangles, num_vertices, closed in (
            (np.array([[0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4], [1, 0, 5], [2, 1, 5], [3, 2, 5], [0, 3, 5]],
                      np.int32), 6, True),
            (np.array([[0, 1, 2], [2, 1, 3], [2, 3, 4]], np.int32), 5, False)):
        plan = _loopsub.Plan(triangles, num_vertices, levels, rules="opensubdiv")
        t = plan.triangles
        edges, triangle_edges = plan.output_edges()
        assert edges.dtype == np.int32 and triangle_edges.dtype == np.int32 and triangle_edges.shape == t.shape
        joined = edges[triangle_edges]  # (T, 3, 2)
        for i in range(3):
            assert np.array_equal(np.sort(joined[:, i], axis=1), np.sort(t[:, [i, (i + 1) % 3]], axis=1))
        assert len(np.unique(np.sort(edges, axis=1), axis=0)) == len(edges)
        assert np.array_equal(np.unique(triangle_edges), np.arange(len(edges)))
        if closed:
            assert plan.num_output_vertices - len(edges) + len(t) == 2
        before = plan.level_edges(levels - 1)
        midpoints = plan.level_num_vertices(levels - 1) + np.arange(len(before))
        assert np.array_equal(edges[0:2 * len(before):2], np.column_stack([before[:, 0], midpoints]))
        assert np.array_equal(edges[1:2 * len(before):2], np.column_stack([midpoints, before[:, 1]]))


@pytest.mark.parametrize("rules", ["opensubdiv", "hoppe94"])
@pytest.mark.parametrize("levels", [1, 2, 3])
def test_tagged_edges_are_numbered_as_output_edges(levels, rules):
    # An open strip with its inner edge (1, 2) creased: the numbers name the same edges as the pairs, every boundary
    # edge of the output (in one triangle) is among the sharp ones, and the crease's 2^levels halves are creases.
    triangles = np.array([[0, 1, 2], [2, 1, 3], [2, 3, 4]], np.int32)
    plan = _loopsub.Plan(triangles, 5, levels, rules=rules, crease_edges=np.array([[1, 2]], np.int32),
                         crease_sharpness=np.array([10.0], np.float32))
    edges, triangle_edges = plan.output_edges()
    for numbers, pairs in ((plan.sharp_edge_indices, plan.sharp_edges), (plan.crease_edge_indices, plan.crease_edges)):
        assert numbers.dtype == np.int32 and len(numbers) == len(pairs)
        np.testing.assert_array_equal(np.sort(edges[numbers], axis=1), np.sort(pairs, axis=1))
    boundary = np.flatnonzero(np.bincount(triangle_edges.ravel(), minlength=len(edges)) == 1)
    assert np.isin(boundary, plan.sharp_edge_indices).all()
    assert len(plan.crease_edge_indices) == 2 ** levels
    assert np.isin(plan.crease_edge_indices, plan.sharp_edge_indices).all()


def test_output_edge_parents_name_the_input_edges():
    # A quad as two triangles, its diagonal (0, 2) unnumbered on both sides: the halves of each numbered edge carry
    # its number (the halves of level-0 edge e are 2e and 2e + 1; edges are numbered by their first corner), the
    # diagonal's halves and the edges inside the triangles -1; one level further, every half of a half keeps it.
    triangles = np.array([[0, 1, 2], [0, 2, 3]], np.int32)
    side_edges = np.array([[5, 6, -1], [-1, 7, 8]], np.int32)
    plan = _loopsub.Plan(triangles, 4, 1, threads=2)
    parents = plan.output_edge_parents(side_edges)
    assert parents.dtype == np.int32
    assert parents.tolist() == [5, 5, 6, 6, -1, -1, 7, 7, 8, 8] + [-1] * 6
    deeper = _loopsub.Plan(triangles, 4, 2).output_edge_parents(side_edges)
    assert deeper.tolist() == [n for n in parents.tolist()[:10] for _ in (0, 1)] + [-1] * (len(deeper) - 20)
    # A side numbered on one triangle only gives the edge that number.
    assert plan.output_edge_parents(np.array([[5, 6, 9], [-1, 7, 8]], np.int32))[4:6].tolist() == [9, 9]
    out = np.full(plan.num_output_edges, -7, np.int32)
    assert plan.output_edge_parents(side_edges, out) is out and out.tolist() == parents.tolist()
    for bad, error, message in ((side_edges.astype(np.int64), TypeError, "int32"),
                                (side_edges[:1], ValueError, "shape")):
        with pytest.raises(error, match=message):
            plan.output_edge_parents(bad)
    with pytest.raises(ValueError, match="no levels"):
        _loopsub.Plan(triangles, 4, 0).output_edge_parents(side_edges)


def test_output_edges_write_into_given_arrays():
    # Into arrays the caller owns (a mesh's own edge and corner arrays, say): the same values as new arrays, the very
    # arrays returned, num_output_edges their length; a wrong dtype, shape, layout, a read-only or overlapping
    # array is refused before anything is written.
    p, t = icosahedron()
    plan = _loopsub.Plan(t, len(p), 2, threads=2)
    edges, triangle_edges = plan.output_edges()
    assert plan.num_output_edges == len(edges)
    edge_out = np.full((plan.num_output_edges, 2), -7, np.int32)
    corner_out = np.full(3 * plan.num_output_triangles, -7, np.int32)  # one per corner, as a mesh keeps them
    returned = plan.output_edges(edge_out, corner_out.reshape(-1, 3))
    assert returned[0] is edge_out and np.shares_memory(returned[1], corner_out)
    np.testing.assert_array_equal(edge_out, edges)
    np.testing.assert_array_equal(corner_out.reshape(-1, 3), triangle_edges)
    # With the corners' vertices too (a mesh's corner array): the output triangles, the same edges.
    vertex_out = np.full_like(corner_out, -7)
    edge_out[:] = corner_out[:] = -7
    plan.output_edges(edge_out, corner_out.reshape(-1, 3), vertex_out.reshape(-1, 3))
    np.testing.assert_array_equal(vertex_out.reshape(-1, 3), plan.triangles)
    np.testing.assert_array_equal(edge_out, edges)
    np.testing.assert_array_equal(corner_out.reshape(-1, 3), triangle_edges)
    untouched = np.full_like(edge_out, -7)
    for bad, error, message in ((untouched.astype(np.int64), TypeError, "int32"),
                                (untouched[:-1], ValueError, "shape"),
                                (np.full((2, len(edges)), -7, np.int32).T, ValueError, "C-contiguous")):
        with pytest.raises(error, match=message):
            plan.output_edges(bad, np.empty_like(triangle_edges))
    read_only = untouched.copy()
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match="writeable"):
        plan.output_edges(read_only)
    both = np.full(2 * len(edges) + 3 * len(triangle_edges), -7, np.int32)
    with pytest.raises(ValueError, match="share memory"):
        plan.output_edges(both[:2 * len(edges)].reshape(-1, 2), both[len(edges):len(edges) + 3 * len(triangle_edges)]
                          .reshape(-1, 3))
    with pytest.raises(ValueError, match="share memory"):
        plan.output_edges(untouched, corner_out.reshape(-1, 3), corner_out.reshape(-1, 3))
    with pytest.raises(ValueError, match="writeable"):
        plan.output_edges(untouched, corner_out.reshape(-1, 3), plan.triangles)
    assert (untouched == -7).all() and (both == -7).all()


def test_output_edges_need_a_level_and_no_holes():
    p, t = icosahedron()
    with pytest.raises(ValueError, match="no levels"):
        _loopsub.Plan(t, len(p), 0).output_edges()
    with pytest.raises(ValueError, match="no levels"):
        _loopsub.Plan(t, len(p), 0).num_output_edges
    with pytest.raises(ValueError, match="holes"):
        _loopsub.Plan(t, len(p), 1, hole_triangles=np.array([0], np.int32)).output_edges()
