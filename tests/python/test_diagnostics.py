"""The core's input problems in Python: InputError (a ValueError) says where as attributes, diagnose() lists every
problem and note. Every expected index below is worked out by hand from the small meshes here."""
import numpy as np
import pytest

import _loopsub
from conftest import icosahedron, tetrahedron


def raised(call, *args, **kwargs):
    with pytest.raises(_loopsub.InputError) as info:
        call(*args, **kwargs)
    return info.value


def test_input_error_is_a_value_error():
    assert issubclass(_loopsub.InputError, ValueError)


def test_vertex_out_of_range():
    p, t = tetrahedron()
    t = t.copy()
    t[2, 1] = 9
    for error in (raised(_loopsub.Plan, t, 4), raised(_loopsub.subdivide, p, t, 1)):
        assert (error.kind, error.element, error.index, error.corner, error.refers_to, error.other) == \
            ("vertex_out_of_range", "triangle", 2, 1, 9, 4)
        assert (error.layer, error.channel, error.value) == (None, None, None)
        assert str(error) == "triangle 2 refers to vertex 9, outside 0..3 (the mesh has 4 vertices)"
        assert error.problem.message == str(error) and not error.problem.is_note


def test_degenerate_triangle():
    p, t = tetrahedron()
    t = np.vstack([t, [[3, 1, 1]]]).astype(np.int32)
    error = raised(_loopsub.subdivide, p, t, 1)
    assert (error.kind, error.element, error.index, error.corner, error.refers_to) == \
        ("degenerate_triangle", "triangle", 4, 2, 1)


def test_tags():
    p, t = tetrahedron()
    error = raised(_loopsub.Plan, t, 4, crease_edges=np.array([[0, 1], [1, 7]], np.int32))
    assert (error.kind, error.element, error.index, error.refers_to) == ("vertex_out_of_range", "crease_edge", 1, 7)
    error = raised(_loopsub.Plan, t, 4, corner_vertices=np.array([2], np.int32),
                   corner_sharpness=np.array([-2], np.float32))
    assert (error.kind, error.element, error.index, error.value) == ("bad_sharpness", "corner_vertex", 0, -2.0)
    error = raised(_loopsub.Plan, t, 4, cone_vertices=np.array([0, -3], np.int32), rules="hoppe94")
    assert (error.kind, error.element, error.index, error.refers_to) == ("vertex_out_of_range", "cone", 1, -3)
    error = raised(_loopsub.Plan, t, 4, hole_triangles=np.array([4], np.int32))
    assert (error.kind, error.element, error.index, error.refers_to, error.other) == \
        ("triangle_out_of_range", "hole", 0, 4, 4)


def test_crease_that_is_no_edge():
    quad = np.array([[0, 1, 2], [0, 2, 3]], np.int32)  # 1-3 is no edge; 0-2 is the diagonal
    error = raised(_loopsub.Plan, quad, 4, crease_edges=np.array([[0, 2], [1, 3]], np.int32))
    assert (error.kind, error.element, error.index, error.refers_to, error.other) == \
        ("not_an_edge", "crease_edge", 1, 1, 3)
    assert str(error) == "crease edge 1 (1, 3) is not an edge of the mesh"


def test_face_varying_value_index_out_of_range():
    p, t = tetrahedron()
    indices = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, -1, 2]], np.int32)
    error = raised(_loopsub.Plan, t, 4, face_varying_indices=[indices])
    assert (error.kind, error.element, error.index, error.corner, error.refers_to, error.other, error.layer) == \
        ("value_out_of_range", "triangle", 3, 1, -1, 4, 0)


def test_non_finite_values():
    p, t = tetrahedron()
    p = p.copy()
    p[3, 2] = np.nan
    error = raised(_loopsub.Plan(t, 4).evaluate, p)
    assert (error.kind, error.element, error.index, error.channel) == ("non_finite_value", "vertex", 3, 2)
    assert np.isnan(error.value)
    # Per corner, a layer after the one given: triangle 1, corner 0, channel 1.
    uv = np.zeros((4, 3, 2), np.float32)
    uv[1, 0, 1] = np.inf
    given = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], np.int32)
    error = raised(_loopsub.subdivide, tetrahedron()[0], t, 1, face_varying={"uv": uv}, face_varying_indices=[given])
    assert (error.kind, error.element, error.index, error.corner, error.channel, error.layer, error.value) == \
        ("non_finite_value", "triangle", 1, 0, 1, 1, np.inf)
    assert str(error).startswith("face_varying['uv']: triangle 1, corner 0")
    # A face-varying layer's values: value 2 of layer 0, channel 0.
    plan = _loopsub.Plan(t, 4, face_varying_indices=[given])
    values = np.zeros((4, 2), np.float32)
    values[2, 0] = -np.inf
    error = raised(plan.evaluate_face_varying, values, layer=0)
    assert (error.kind, error.element, error.index, error.layer, error.channel) == \
        ("non_finite_value", "face_varying_value", 2, 0, 0)
    # Per corner without a layer.
    corners = np.zeros((4, 3), np.float32)
    corners[3, 2] = np.nan
    error = raised(plan.evaluate_face_varying, corners)
    assert (error.kind, error.element, error.index, error.corner, error.layer) == \
        ("non_finite_value", "triangle", 3, 2, None)


def test_value_too_large():
    p, t = tetrahedron()
    p = p.copy()
    p[1, 0] = 3e38
    error = raised(_loopsub.subdivide, p, t, 1)
    assert (error.kind, error.element, error.index, error.channel) == ("value_too_large", "vertex", 1, 0)
    assert error.value == np.float32(3e38) and 0 < error.limit < 3e38 and error.other > 0


def test_a_tessellations_rated_edges():
    """A Tessellation's edges and edge_rates: the first row that names no edge of the mesh, or whose rate is outside
    1..4096, with its row, its ends and the rate."""
    positions, triangles = icosahedron()
    a, b, c = (int(v) for v in triangles[0])
    edges = np.array([[a, b], [b, c], [a, a]], np.int32)
    error = raised(_loopsub.Tessellation, triangles, len(positions), 2, edges=edges,
                   edge_rates=np.array([3, 5, 2], np.int32))
    assert (error.kind, error.element, error.index, error.refers_to, error.other) == \
        ("not_an_edge", "rated_edge", 2, a, a)
    error = raised(_loopsub.Tessellation, triangles, len(positions), 2, edges=edges,
                   edge_rates=np.array([3, 0, 2], np.int32))
    assert (error.kind, error.element, error.index, error.refers_to, error.other) == \
        ("rate_out_of_range", "rated_edge", 1, b, c)
    assert (error.value, error.limit, error.channel) == (0.0, 4096.0, None)
    assert str(error) == f"tessellation: rated edge 1 ({b}, {c}) has rate 0; a rate must be between 1 and 4096"
    assert raised(_loopsub.Tessellation, triangles, len(positions), 0).problem is None  # an argument, not data


def test_a_tessellations_positions_and_layer_values():
    positions, triangles = icosahedron()
    uv_indices = np.arange(60, dtype=np.int32).reshape(20, 3)
    tessellation = _loopsub.Tessellation(triangles, len(positions), 3, face_varying_indices=[uv_indices])
    bad = positions.copy()
    bad[4, 1] = np.inf
    error = raised(tessellation.evaluate, bad)
    assert (error.kind, error.element, error.index, error.channel) == ("non_finite_value", "vertex", 4, 1)
    bad[4, 1] = 3e38
    error = raised(tessellation.evaluate, bad)
    assert (error.kind, error.element, error.index, error.channel) == ("value_too_large", "vertex", 4, 1)
    assert error.limit == np.float32(np.finfo(np.float32).max / 64)
    uvs = np.zeros((60, 2), np.float32)
    uvs[33, 0] = np.nan
    error = raised(tessellation.evaluate_face_varying, uvs)
    assert (error.kind, error.element, error.index, error.layer, error.channel) == \
        ("non_finite_value", "face_varying_value", 33, 0, 0)


def test_screen_space_rates_camera_triangles_and_positions():
    positions, triangles = icosahedron()
    camera = np.eye(4, dtype=np.float32)
    camera[3, 2] = np.nan
    error = raised(_loopsub.screen_space_rates, positions, triangles, camera, (100, 100))
    assert (error.kind, error.element, error.index, error.channel, error.refers_to) == \
        ("non_finite_value", "camera", 14, None, None)
    assert str(error) == ("screen_space_rates: the camera's world_to_clip entry 14 (row 3, column 2) has a "
                          "non-finite value (nan)")
    bad = triangles.copy()
    bad[5, 2] = 12
    error = raised(_loopsub.screen_space_rates, positions, bad, np.eye(4, dtype=np.float32), (100, 100))
    assert (error.kind, error.element, error.index, error.corner, error.refers_to, error.other) == \
        ("vertex_out_of_range", "triangle", 5, 2, 12, 12)


def test_errors_of_the_call_have_no_problem():
    error = raised(_loopsub.Plan, tetrahedron()[1], 4, levels=-1)
    assert error.kind is None and error.problem is None and error.index is None


def test_diagnose_lists_every_problem_then_notes():
    p, t = tetrahedron()
    t = np.vstack([t, [[0, 0, 1], [2, 5, 1]]]).astype(np.int32)
    problems = _loopsub.diagnose(t, 4, crease_edges=np.array([[0, 9]], np.int32))
    assert [(q.kind, q.element, q.index) for q in problems] == [
        ("degenerate_triangle", "triangle", 4), ("vertex_out_of_range", "triangle", 5),
        ("vertex_out_of_range", "crease_edge", 0)]
    p = p.copy()
    p[0, 1] = np.nan
    uv = np.zeros((4, 3), np.float32)
    uv[2, 1] = np.inf
    problems = _loopsub.diagnose(tetrahedron()[1], 4, positions=p, face_varying=uv)
    assert [(q.kind, q.element, q.index, q.corner, q.channel, q.layer) for q in problems] == [
        ("non_finite_value", "vertex", 0, None, 1, None), ("non_finite_value", "triangle", 2, 1, 0, 0)]
    assert _loopsub.diagnose(tetrahedron()[1], 4, positions=tetrahedron()[0]) == []


def test_edges_run_the_same_way_are_notes():
    # An octahedron whose triangle 0 is wound against its neighbours 1 (across its side 0), 2 (side 2) and 6 (side 1).
    t = np.array([[4, 1, 0], [1, 0, 5], [1, 2, 4], [2, 1, 5], [2, 3, 4], [3, 2, 5], [3, 0, 4], [0, 3, 5]], np.int32)
    expected = [(1, 0, 0), (2, 2, 0), (6, 1, 0)]
    notes = _loopsub.diagnose(t, 6)
    assert all(note.is_note and note.kind == "runs_the_same_way" for note in notes)
    assert sorted((note.index, note.corner, note.other) for note in notes) == expected
    plan = _loopsub.Plan(t, 6)
    assert sorted((note.index, note.corner, note.other) for note in plan.notes) == expected
    assert _loopsub.Plan(tetrahedron()[1], 4).notes == []
    tessellation = _loopsub.Tessellation(t, 6, 2)
    assert sorted((note.index, note.corner, note.other) for note in tessellation.notes) == expected
    assert _loopsub.Tessellation(tetrahedron()[1], 4, 2).notes == []


def test_measure_names_come_from_the_core():
    p, t = tetrahedron()
    with pytest.raises(ValueError, match="measure must be 'length' or 'deviation', got 'area'"):
        _loopsub.screen_space_rates(p, t, np.eye(4, dtype=np.float32), (100, 100), 1.0, 8, "area")
