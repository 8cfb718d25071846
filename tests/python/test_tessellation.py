"""The Tessellation object: the limit surface at a rate per edge (issue 25), as numpy arrays without copies."""
import gc

import numpy as np
import pytest

import _loopsub
from conftest import assert_same_point_sets, edges_of, grid, icosahedron


def test_rate_two_to_the_l_is_level_l_on_the_limit_surface():
    positions, triangles = icosahedron()
    for levels in (0, 1, 2):
        tessellation = _loopsub.Tessellation(triangles, len(positions), 2**levels, rules="opensubdiv")
        points, normals = tessellation.evaluate(positions)
        plan = _loopsub.Plan(triangles, len(positions), levels, rules="opensubdiv", limit_surface=True)
        expected = plan.evaluate(positions)
        assert tessellation.levels == levels
        assert points.shape == (plan.num_output_vertices, 3) and points.dtype == np.float32
        assert tessellation.triangles.shape == (plan.num_output_triangles, 3)
        assert_same_point_sets(points, expected, 1e-6)
        assert normals.shape == (tessellation.num_face_points, 3)
        np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-6)


def test_counts_and_views_for_rates_per_edge():
    positions, triangles = grid(5, seed=3, height=0.2)
    edges = np.array(sorted(edges_of(triangles)), np.int32)
    rates = (np.arange(len(edges)) % 4 + 1).astype(np.int32)
    tessellation = _loopsub.Tessellation(triangles, len(positions), 1, edges=edges, edge_rates=rates,
                                         rules="opensubdiv")
    # Every edge's inner points once, and each triangle's inner lattice of its largest rate (or its centre).
    inner = 0
    rate_of = {tuple(sorted(e)): r for e, r in zip(edges.tolist(), rates.tolist())}
    for t in triangles.tolist():
        r = [rate_of[tuple(sorted((t[k], t[(k + 1) % 3])))] for k in range(3)]
        n = max(r)
        inner += 1 if (len(set(r)) > 1 and n < 3) else (n - 1) * (n - 2) // 2
    assert tessellation.num_points == len(positions) + int((rates - 1).sum()) + inner
    for name in ("triangles", "parent_triangles", "corner_face_points", "face_point_parameters"):
        view = getattr(tessellation, name)
        assert not view.flags.writeable
        assert view.base is not None
    # A face point's parameters place it in its parent triangle: barycentric coordinates in [0, 1].
    uv = tessellation.face_point_parameters
    assert uv.min() >= 0.0 and (uv.sum(axis=1) <= 1.0 + 1e-6).all()
    points, normals = tessellation.evaluate(positions)
    assert np.isfinite(points).all() and np.isfinite(normals).all()


def test_output_edges_name_each_pair_of_ends_once():
    positions, triangles = grid(4, seed=1, height=0.1)
    tessellation = _loopsub.Tessellation(triangles, len(positions), 3)
    edge_vertices, triangle_edges = tessellation.output_edges()
    t = tessellation.triangles
    assert edge_vertices.shape[1] == 2 and triangle_edges.shape == t.shape
    sides = np.stack([t, np.roll(t, -1, axis=1)], axis=2)  # (T, 3, 2): side k joins corners k and k + 1
    assert np.array_equal(np.sort(edge_vertices[triangle_edges], axis=2), np.sort(sides, axis=2))
    assert len({tuple(pair) for pair in np.sort(edge_vertices, axis=1).tolist()}) == len(edge_vertices)
    assert len(np.unique(triangle_edges)) == len(edge_vertices)


def _seamed_grid():
    """A bent 6 x 6 grid with UVs split along the column x = 3: the right side's values moved, a real seam."""
    positions, triangles = grid(6, seed=2, height=0.3)
    middle = np.unique(positions[:, 0])[3]
    on_seam = np.abs(positions[:, 0] - middle) < 1e-6
    right = positions[triangles][:, :, 0].mean(axis=1) > middle
    copy = {v: len(positions) + k for k, v in enumerate(np.flatnonzero(on_seam))}
    indices = triangles.copy()
    for f in np.flatnonzero(right):
        for k in range(3):
            if on_seam[indices[f, k]]:
                indices[f, k] = copy[indices[f, k]]
    values = np.concatenate([positions[:, :2], positions[on_seam, :2] + 0.05]).astype(np.float32)
    return positions, triangles, indices.astype(np.int32), values


@pytest.mark.parametrize("mode", ["none", "corners", "corners-plus1", "corners-plus2", "boundaries", "all"])
def test_a_layer_at_rate_two_to_the_l_is_the_plans_layer_at_level_l(mode):
    positions, triangles, indices, values = _seamed_grid()
    for levels in (1, 2):
        plan = _loopsub.Plan(triangles, len(positions), levels, rules="opensubdiv", limit_surface=True,
                             uv_interpolation=mode, face_varying_indices=[indices])
        plan_points = plan.evaluate(positions)[plan.triangles].reshape(-1, 3)
        plan_uvs = plan.evaluate_face_varying(values, layer=0)[plan.face_varying_indices(0)].reshape(-1, 2)
        tessellation = _loopsub.Tessellation(triangles, len(positions), 2**levels, rules="opensubdiv",
                                             uv_interpolation=mode, face_varying_indices=[indices])
        assert tessellation.num_face_varying_layers == 1
        points, _ = tessellation.evaluate(positions)
        layer = tessellation.evaluate_face_varying(values)
        assert layer.shape == (tessellation.num_face_points, 2) and layer.dtype == np.float32
        tess_points = points[tessellation.triangles].reshape(-1, 3)
        tess_uvs = layer[tessellation.corner_face_points].reshape(-1, 2)
        # Each corner of the tessellation is a corner of the plan in the same input triangle at the same place.
        plan_parents = np.repeat(plan.parent_triangles, 3)
        tess_parents = np.repeat(tessellation.parent_triangles, 3)
        for parent in range(len(triangles)):
            ours = np.flatnonzero(tess_parents == parent)
            theirs = np.flatnonzero(plan_parents == parent)
            distance = np.linalg.norm(tess_points[ours, None, :] - plan_points[None, theirs, :], axis=2)
            nearest = theirs[distance.argmin(axis=1)]
            assert distance.min(axis=1).max() < 1e-5
            np.testing.assert_allclose(tess_uvs[ours], plan_uvs[nearest], atol=2e-6)


def test_views_keep_the_tessellation_alive_and_out_is_written_in_place():
    positions, triangles = icosahedron()
    tessellation = _loopsub.Tessellation(triangles, len(positions), 3)
    triangles_view = tessellation.triangles
    out = np.zeros((tessellation.num_points, 3), np.float32)
    normals = np.zeros((tessellation.num_face_points, 3), np.float32)
    result, result_normals = tessellation.evaluate(positions, out=out, normals=normals)
    assert result is out and result_normals is normals and np.abs(out).sum() > 0
    del tessellation
    gc.collect()
    assert triangles_view.max() < len(out)


def test_boundary_none_leaves_out_the_faces_a_plan_leaves_out():
    """boundary="none": the triangles a plan leaves out get no triangles, as the plan decides."""
    positions, triangles = grid(6, seed=4, height=0.2)
    plan = _loopsub.Plan(triangles, len(positions), 1, rules="opensubdiv", boundary="none")
    tessellation = _loopsub.Tessellation(triangles, len(positions), 3, rules="opensubdiv", boundary="none")
    assert 0 < len(tessellation.triangles) < 9 * len(triangles)
    assert set(tessellation.parent_triangles.tolist()) == set(plan.parent_triangles.tolist())
    assert len(tessellation.triangles) == 9 * len(set(plan.parent_triangles.tolist()))
    points, _ = tessellation.evaluate(positions)
    assert np.isfinite(points).all()


def test_bad_input_raises():
    positions, triangles = icosahedron()
    with pytest.raises(ValueError, match="uniform_rate must be between 1 and 4096, got 0"):
        _loopsub.Tessellation(triangles, len(positions), 0)
    with pytest.raises(ValueError, match=r"rated edge 0 \(0, 3\) is not an edge of the mesh"):
        _loopsub.Tessellation(triangles, len(positions), 2, edges=np.array([[0, 3]], np.int32),
                              edge_rates=np.array([2], np.int32))
    with pytest.raises(ValueError, match="edges and edge_rates go together"):
        _loopsub.Tessellation(triangles, len(positions), 2, edges=np.array([[0, 11]], np.int32))
    with pytest.raises(TypeError, match="edge_rates must have dtype int32"):
        _loopsub.Tessellation(triangles, len(positions), 2, edges=np.array([[0, 11]], np.int32),
                              edge_rates=np.array([2.0]))
    tessellation = _loopsub.Tessellation(triangles, len(positions), 2)
    with pytest.raises(ValueError, match=r"positions must have shape \(N=12, 3\)"):
        tessellation.evaluate(positions[:5])
    with pytest.raises(ValueError, match="non-finite|finite"):
        bad = positions.copy()
        bad[0, 0] = np.nan
        tessellation.evaluate(bad)


def test_a_cut_at_new_rates_reusing_the_input_topology_is_the_cut_made_anew():
    """reuse= takes an earlier cut's input_topology: the cut at new rates is the one made anew, also where the earlier
    was of other tags (nothing is taken then), and after the earlier cut is gone."""
    positions, triangles = icosahedron()
    uv_indices = np.arange(60, dtype=np.int32).reshape(20, 3)
    uvs = np.random.default_rng(5).random((60, 2)).astype(np.float32)
    tagged = {"crease_edges": np.array([[0, 1]], np.int32), "crease_sharpness": np.array([1.5], np.float32)}
    edges, rates = _loopsub.screen_space_rates(positions, triangles, perspective_down_z(), (100, 100))
    rates = (np.arange(len(rates)) % 5 + 1).astype(np.int32)
    for earlier_tags in (tagged, {}):
        kept = _loopsub.Tessellation(triangles, len(positions), 3, rules="opensubdiv",
                                     face_varying_indices=[uv_indices], **earlier_tags).input_topology
        gc.collect()
        anew, reused = (_loopsub.Tessellation(triangles, len(positions), edges=edges, edge_rates=rates, reuse=reuse,
                                              rules="opensubdiv", face_varying_indices=[uv_indices], **tagged)
                        for reuse in (None, kept))
        assert np.array_equal(anew.triangles, reused.triangles)
        for a, b in zip(anew.evaluate(positions), reused.evaluate(positions)):
            assert np.array_equal(a, b)
        assert np.array_equal(anew.evaluate_face_varying(uvs), reused.evaluate_face_varying(uvs))
    with pytest.raises(TypeError, match="reuse must be an InputTopology"):
        _loopsub.Tessellation(triangles, len(positions), 2, reuse=anew)


def test_the_memory_limit_refuses_below_what_the_tessellation_counts():
    """estimated_bytes is what memory_limit_bytes is checked against: a limit one byte below it raises MemoryError
    with it as required_bytes, a limit at it is met. It grows with the rate."""
    positions, triangles = icosahedron()
    counted = _loopsub.Tessellation(triangles, len(positions), 16).estimated_bytes
    assert _loopsub.Tessellation(triangles, len(positions), 32).estimated_bytes > 3 * counted
    assert _loopsub.Tessellation(triangles, len(positions), 16, memory_limit_bytes=counted).estimated_bytes == counted
    with pytest.raises(MemoryError) as refused:
        _loopsub.Tessellation(triangles, len(positions), 16, memory_limit_bytes=counted - 1)
    assert refused.value.required_bytes == counted


def perspective_down_z(width=100, height=100):
    """A camera at the origin looking down -z, OpenGL's perspective with a 90 degree vertical field of view."""
    near, far = 0.1, 100.0
    return np.array([[height / width, 0, 0, 0], [0, 1, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]], np.float32)


def test_screen_space_rates_cut_an_edge_by_its_length_on_screen():
    # A unit edge at distance 2 spans 25 of 100 pixels: 7 segments of 4 pixels (6.25, rounded up).
    positions = np.array([[-0.5, 0, -2], [0.5, 0, -2], [0, 0.5, -2]], np.float32)
    triangles = np.array([[0, 1, 2]], np.int32)
    edges, rates = _loopsub.screen_space_rates(positions, triangles, perspective_down_z(), (100, 100),
                                               pixels=4.0, max_rate=64)
    assert edges.dtype == np.int32 and rates.dtype == np.int32 and edges.shape == (3, 2)
    rate_of = {tuple(sorted(e)): r for e, r in zip(edges.tolist(), rates.tolist())}
    assert rate_of[(0, 1)] == 7
    far_edges, far_rates = _loopsub.screen_space_rates(positions * np.float32(10), triangles, perspective_down_z(),
                                                       (100, 100), pixels=4.0)
    assert (far_rates <= rates).all() and far_rates.min() >= 1
    tessellation = _loopsub.Tessellation(triangles, len(positions), edges=edges, edge_rates=rates)
    assert tessellation.num_points > len(positions)
    with pytest.raises(ValueError, match="pixels must be a positive number"):
        _loopsub.screen_space_rates(positions, triangles, perspective_down_z(), (100, 100), pixels=0.0)
    with pytest.raises(ValueError, match="measure must be 'length' or 'deviation'"):
        _loopsub.screen_space_rates(positions, triangles, perspective_down_z(), (100, 100), measure="area")
    # By deviation a flat grid, however near, is cut only where its limit rounds it: at its four corners. Along its
    # straight sides and inside, one segment an edge.
    grid_positions, grid_triangles = grid(7)
    grid_positions[:, 2] = -2.0
    flat_edges, flat = _loopsub.screen_space_rates(grid_positions, grid_triangles, perspective_down_z(), (100, 100),
                                                   pixels=0.01, measure="deviation")
    corners = np.array([[0, 0], [0, 1], [1, 0], [1, 1]], np.float32)
    ends = grid_positions[flat_edges][:, :, :2]  # (E, 2 ends, xy)
    cells_from_a_corner = np.abs(ends[:, :, None, :] - corners[None, None]).max(axis=-1).min(axis=-1) * 6
    assert (flat[(cells_from_a_corner > 2.01).any(axis=1)] == 1).all() and (flat > 1).any()
    bad = grid_positions.copy()
    bad[9, 1] = np.nan  # inside the grid: by deviation its neighbours' edges read it too
    for measure in ("length", "deviation"):
        with pytest.raises(ValueError, match=r"vertex 9 has a non-finite value \(nan\) in channel 1"):
            _loopsub.screen_space_rates(bad, grid_triangles, perspective_down_z(), (100, 100), measure=measure)
    with pytest.raises(ValueError, match=r"world_to_clip must have shape \(4, 4\)"):
        _loopsub.screen_space_rates(positions, triangles, np.eye(3, dtype=np.float32), (100, 100))
