"""_loopsub.option_names() and _loopsub.weld_corner_values(): the core's one table of option names and its one corner
welding, which the add-on can call instead of keeping copies."""
import numpy as np
import pytest

import _loopsub
from conftest import grid, icosahedron

EXPECTED_NAMES = {
    "rules": ("hoppe94", "opensubdiv"),
    "boundary": ("edges", "edges-and-corners", "none"),
    "crease_method": ("uniform", "chaikin"),
    "uv_interpolation": ("none", "corners", "corners-plus1", "corners-plus2", "boundaries", "all"),
    "level_tables": ("auto", "stored", "derived"),
}


def test_option_names_are_what_plan_and_subdivide_take():
    names = _loopsub.option_names()
    assert names == EXPECTED_NAMES
    names["rules"] = ()  # a new dict each call
    assert _loopsub.option_names() == EXPECTED_NAMES
    p, t = icosahedron()
    for keyword, values in EXPECTED_NAMES.items():
        for value in values:
            plan = _loopsub.Plan(t, len(p), 2, **{keyword: value})
            if keyword in ("rules", "uv_interpolation", "level_tables"):
                assert getattr(plan, keyword) == value
        with pytest.raises(ValueError) as error:
            _loopsub.Plan(t, len(p), 1, **{keyword: "other"})
        listed = ", ".join(f"'{v}'" for v in values[:-1]) + f" or '{values[-1]}'"
        assert str(error.value) == f"{keyword} must be {listed}, got 'other'"


def partition(indices):
    """The corners grouped by value, whatever the numbering."""
    groups = {}
    for corner, index in enumerate(np.asarray(indices).ravel()):
        groups.setdefault(int(index), []).append(corner)
    return sorted(groups.values())


def test_weld_corner_values_by_hand():
    # Two triangles sharing the edge 1-2; vertex 2 has the same UV on both (-0.0 and 0.0 alike), vertex 1 two.
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    uvs = np.array([[[0, 0], [1, 0], [0, 1]], [[5, 0], [5, 1], [-0.0, 1]]], np.float32)
    indices, values = _loopsub.weld_corner_values(triangles, 4, uvs)
    assert indices.dtype == np.int32 and indices.shape == (2, 3) and indices.flags.writeable
    assert values.dtype == np.float32 and values.shape == (5, 2)
    # Vertex by vertex, each vertex's values in the order of their first corner.
    np.testing.assert_array_equal(indices, [[0, 1, 3], [2, 4, 3]])
    np.testing.assert_array_equal(values, [[0, 0], [1, 0], [5, 0], [0, 1], [5, 1]])
    # One channel: (M, 3) in, (V,) out.
    indices, values = _loopsub.weld_corner_values(triangles, 4, np.ascontiguousarray(uvs[:, :, 0]))
    np.testing.assert_array_equal(indices, [[0, 1, 3], [2, 4, 3]])
    np.testing.assert_array_equal(values, [0, 1, 5, 0, 5])


def reference_partition(triangles, uvs):
    """The corners grouped by (vertex, value), written plainly: what welding means, -0.0 and 0.0 alike."""
    groups = {}
    for corner, (vertex, value) in enumerate(zip(np.asarray(triangles).ravel(), uvs.reshape(-1, uvs.shape[-1]))):
        groups.setdefault((int(vertex), tuple(float(x) + 0.0 for x in value)), []).append(corner)
    return sorted(groups.values())


def test_weld_corner_values_groups_corners_by_vertex_and_value():
    positions, triangles = grid(6, seed=3)
    rng = np.random.default_rng(5)
    uvs = np.round(positions[triangles][:, :, :2] * 2) / 2  # few distinct values: many shared, some seams
    uvs[rng.random(uvs.shape[:2]) < 0.2] = 7.0
    uvs[0, 0, 0] = -0.0
    uvs = np.ascontiguousarray(uvs, np.float32)
    indices, values = _loopsub.weld_corner_values(triangles, len(positions), uvs)
    assert partition(indices) == reference_partition(triangles, uvs)
    np.testing.assert_array_equal(values[indices], uvs)


def test_weld_corner_values_keeps_indices_while_a_value_moves():
    """What the add-on's live entry relies on to keep its plan while a UV is dragged."""
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    uvs = np.array([[[0, 0], [1, 0], [0, 1]], [[5, 0], [5, 1], [-0.0, 1]]], np.float32)
    indices, _ = _loopsub.weld_corner_values(triangles, 4, uvs)
    assert indices[0, 2] == indices[1, 2] and indices[0, 1] != indices[1, 0]
    for moved in ([0.5, 0.5], [9, 9], [-1, -1]):  # whether it now sorts before or after the vertex's other value
        dragged = uvs.copy()
        dragged[1, 0] = moved
        dragged_indices, dragged_values = _loopsub.weld_corner_values(triangles, 4, dragged)
        np.testing.assert_array_equal(dragged_indices, indices)
        np.testing.assert_array_equal(dragged_values[indices], dragged + 0.0)
    # Equal values on different vertices stay different values.
    indices, values = _loopsub.weld_corner_values(triangles, 4, np.zeros((2, 3, 2), np.float32))
    assert len(values) == 4 and indices[0, 1] == indices[1, 0] and indices[0, 2] == indices[1, 2]


def test_a_welded_constant_stays_constant_in_every_uv_mode():
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    uvs = np.array([[[0, 0], [1, 0], [0, 1]], [[5, 0], [5, 1], [0, 1]]], np.float32)
    indices, values = _loopsub.weld_corner_values(triangles, 4, uvs)
    for interpolation in EXPECTED_NAMES["uv_interpolation"]:
        plan = _loopsub.Plan(triangles, 4, 2, rules="opensubdiv", uv_interpolation=interpolation,
                             face_varying_indices=[indices], limit_surface=True)
        refined = plan.evaluate_face_varying(np.full_like(values, 0.25), layer=0)[plan.face_varying_indices(0)]
        assert refined.shape == (plan.num_output_triangles, 3, 2) and np.allclose(refined, 0.25)


def test_subdivide_refines_face_varying_data_as_the_welded_layer():
    positions, triangles = grid(5, seed=1, height=0.3)
    uvs = np.ascontiguousarray(positions[triangles][:, :, :2], np.float32)
    uvs[3] += 0.5  # a seam around triangle 3
    indices, values = _loopsub.weld_corner_values(triangles, len(positions), uvs)
    for interpolation in ("corners", "boundaries", "none"):
        r = _loopsub.subdivide(positions, triangles, 2, rules="opensubdiv", uv_interpolation=interpolation,
                               face_varying={"UVMap": uvs})
        plan = _loopsub.Plan(triangles, len(positions), 2, rules="opensubdiv", uv_interpolation=interpolation,
                             face_varying_indices=[indices])
        refined = plan.evaluate_face_varying(values, layer=0)[plan.face_varying_indices(0)]
        np.testing.assert_array_equal(r["face_varying"]["UVMap"], refined)


def test_weld_corner_values_refuses_what_it_cannot_weld():
    triangles = np.array([[0, 1, 2]], np.int32)
    uvs = np.zeros((1, 3, 2), np.float32)
    with pytest.raises(ValueError, match=r"triangle 0 refers to vertex 2, outside 0..1 \(the mesh has 2 vertices\)"):
        _loopsub.weld_corner_values(triangles, 2, uvs)
    with pytest.raises(ValueError, match="negative count"):
        _loopsub.weld_corner_values(triangles, -1, uvs)
    with pytest.raises(TypeError, match="corner_values must have dtype float32"):
        _loopsub.weld_corner_values(triangles, 3, uvs.astype(np.float64))
    with pytest.raises(ValueError, match=r"corner_values must have shape \(T=1, 3, C\) or \(T=1, 3\)"):
        _loopsub.weld_corner_values(triangles, 3, np.zeros((2, 3, 2), np.float32))
    with pytest.raises(TypeError, match="triangles must have dtype int32"):
        _loopsub.weld_corner_values(triangles.astype(np.int64), 3, uvs)
