"""The add-on's bpy-free model (addon/model/geometry.py and addon/model/settings.py), loaded by path with plain
Python: no Blender needed."""
import importlib.util
import os

import numpy as np
import pytest

import _loopsub

_PATH = os.path.join(os.path.dirname(__file__), "..", "..", "addon", "model", "geometry.py")
_spec = importlib.util.spec_from_file_location("loop_subdivision_geometry", _PATH)
geometry = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(geometry)
_SETTINGS_PATH = os.path.join(os.path.dirname(__file__), "..", "..", "addon", "model", "settings.py")
_settings_spec = importlib.util.spec_from_file_location("loop_subdivision_settings", _SETTINGS_PATH)
settings = importlib.util.module_from_spec(_settings_spec)
_settings_spec.loader.exec_module(settings)


def test_crease_to_sharpness_is_blenders_float32_mapping():
    weights = np.array([0.0, 0.5, 0.6, 0.8, 1.0], np.float32)
    sharpness = geometry.crease_to_sharpness(weights)
    assert sharpness.dtype == np.float32
    # Blender: edge_crease * edge_crease * 10.0f, in float.
    expected = np.array([w * w * np.float32(10.0) for w in weights], np.float32)
    assert np.array_equal(sharpness, expected)
    assert sharpness[-1] == 10.0 and sharpness[1] == 2.5
    assert abs(float(sharpness[2]) - 3.6) < 1e-6 and abs(float(sharpness[3]) - 6.4) < 1e-6


def test_sharpness_to_crease_round_trips_and_clips():
    weights = np.linspace(0, 1, 101, dtype=np.float32)
    back = geometry.sharpness_to_crease(geometry.crease_to_sharpness(weights))
    assert np.abs(back - weights).max() < 1e-6
    assert np.array_equal(geometry.sharpness_to_crease(np.array([-1.0, 0.0, 12.0], np.float32)), [0.0, 0.0, 1.0])


def test_crease_tags_per_rule_set():
    edges = np.array([[0, 1], [1, 2], [2, 0], [0, 3]], np.int32)
    edge_weights = np.array([0.0, 0.3, 0.6, 1.0], np.float32)
    vertex_weights = np.array([0.0, 0.4, 0.0, 0.9], np.float32)

    osd = geometry.crease_tags(edges, edge_weights, vertex_weights, 'OPENSUBDIV', 0.5)
    assert osd["crease_edges"].tolist() == [[1, 2], [2, 0], [0, 3]]
    assert np.array_equal(osd["crease_sharpness"], geometry.crease_to_sharpness(edge_weights[1:]))
    assert osd["corner_vertices"].tolist() == [1, 3]
    assert np.array_equal(osd["corner_sharpness"], geometry.crease_to_sharpness([0.4, 0.9]))

    # Seed rules: the weights go to the core (which applies the threshold to edges); corners are thresholded here.
    seed = geometry.crease_tags(edges, edge_weights, vertex_weights, 'HOPPE94', 0.5)
    assert seed["crease_edges"].tolist() == [[1, 2], [2, 0], [0, 3]]
    assert np.array_equal(seed["crease_sharpness"], edge_weights[1:])
    assert seed["corner_vertices"].tolist() == [3]
    for tags in (osd, seed):
        assert {k: v.dtype for k, v in tags.items()} == {"crease_edges": np.int32, "crease_sharpness": np.float32,
                                                        "corner_vertices": np.int32, "corner_sharpness": np.float32}
        assert all(v.flags.c_contiguous for v in tags.values())


def test_tags_are_accepted_by_the_module():
    positions = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], np.float32)
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    edges = np.array([[1, 2], [0, 1]], np.int32)
    for rules in ('HOPPE94', 'OPENSUBDIV'):
        options = settings.Options(levels=2, rules=rules, boundary='KEEP_CORNERS')
        tags = geometry.crease_tags(edges, np.array([1.0, 0.6], np.float32), np.zeros(4, np.float32), rules, 0.5)
        plan = _loopsub.Plan(triangles, 4, 2, **tags, **options.plan_keywords())
        assert plan.evaluate(positions).shape == (plan.num_output_vertices, 3)


def test_child_crease_weights():
    assert np.allclose(geometry.child_crease_weights(np.array([10.0, 2.6], np.float32), 'OPENSUBDIV'),
                       [1.0, np.sqrt(0.26)])
    kept = np.array([0.6, 1.0], np.float32)
    assert np.array_equal(geometry.child_crease_weights(kept, 'HOPPE94'), kept)


def test_lookup_edges_either_direction():
    table = np.array([[0, 1], [2, 1], [3, 0]], np.int32)
    query = np.array([[1, 0], [1, 2], [0, 3], [2, 3]], np.int32)
    assert geometry.lookup_edges(table, query, 4).tolist() == [0, 1, 2, -1]
    assert geometry.lookup_edges(table[:0], query, 4).tolist() == [-1] * 4


def test_duplicate_triangles():
    triangles = np.array([[0, 1, 2], [2, 1, 0], [1, 1, 3], [0, 2, 3], [3, 0, 2]], np.int32)
    assert geometry.duplicate_triangles(triangles).tolist() == [[0, 1], [3, 4]]
    # Three on the same vertices: both later ones are paired with the first; none without triangles.
    assert geometry.duplicate_triangles(triangles[[3, 0, 4, 1, 3]]).tolist() == [[0, 2], [1, 3], [0, 4]]
    assert geometry.duplicate_triangles(triangles[:0]).tolist() == []
    assert geometry.duplicate_triangles(triangles[[0, 2, 3]]).tolist() == []  # distinct: no pair, nothing to tell
    # Vertex numbers past what three of fit in one 63-bit key (2**21 and more).
    far = triangles.astype(np.int64) * 2**21
    assert geometry.duplicate_triangles(far[[3, 0, 4, 1, 3]]).tolist() == [[0, 2], [1, 3], [0, 4]]


# The unit square as Blender keeps it: one quad (0, 1, 3, 2) that Blender triangulates along its diagonal (1, 2), or
# two triangles whose shared edge (1, 2) is a mesh edge. Each: the mesh's edges, each loop's vertex and edge, and the
# triangles as (corner loops, their vertices).
_SQUARE_AS_BLENDER_KEEPS_IT = {
    "quad": (np.array([[0, 1], [1, 3], [3, 2], [2, 0]], np.int32), np.array([0, 1, 2, 3], np.int32),
             np.array([[0, 1, 3], [1, 2, 3]], np.int32), np.array([[0, 1, 2], [1, 3, 2]], np.int32)),
    "triangles": (np.array([[0, 1], [1, 2], [2, 0], [1, 3], [3, 2]], np.int32), np.array([0, 1, 2, 3, 4, 1], np.int32),
                  np.array([[0, 1, 2], [3, 4, 5]], np.int32), np.array([[0, 1, 2], [1, 3, 2]], np.int32)),
}


def test_side_edges_name_the_mesh_edges_and_leave_diagonals_out():
    edges, loop_edges, loops, triangles = _SQUARE_AS_BLENDER_KEEPS_IT["quad"]
    assert geometry.side_edges(triangles, loops, loop_edges, edges).tolist() == [[0, -1, 3], [1, 2, -1]]
    edges, loop_edges, loops, triangles = _SQUARE_AS_BLENDER_KEEPS_IT["triangles"]
    assert geometry.side_edges(triangles, loops, loop_edges, edges).tolist() == [[0, 1, 2], [3, 4, 1]]


@pytest.mark.parametrize("cage", sorted(_SQUARE_AS_BLENDER_KEEPS_IT))
@pytest.mark.parametrize("levels", [1, 2, 3])
def test_output_edge_parents_follow_the_cage_edges(levels, cage):
    cage_edges, loop_edges, loops, triangles = _SQUARE_AS_BLENDER_KEEPS_IT[cage]
    plan = _loopsub.Plan(triangles, 4, levels, rules="opensubdiv")
    t = plan.triangles
    pairs = plan.output_edges()[0]
    parents = plan.output_edge_parents(geometry.side_edges(triangles, loops, loop_edges, cage_edges))
    # Placed linearly (positions as face-varying data), a child edge lies on the cage edge it names, and on none
    # when it names none (the quad's diagonal is no cage edge): checked against the unit square's geometry, not the
    # numbering.
    square = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], np.float64)
    linear = plan.evaluate_face_varying(np.ascontiguousarray(square[triangles], dtype=np.float32))
    positions = np.zeros((plan.num_output_vertices, 2))
    positions[t.ravel()] = linear.reshape(-1, 2)
    ends = square[cage_edges]  # (E, 2, 2)

    def on_segment(points, segment):
        p0, p1 = segment
        cross = (p1 - p0)[0] * (points[:, 1] - p0[1]) - (p1 - p0)[1] * (points[:, 0] - p0[0])
        return np.all(np.abs(cross) < 1e-6)

    lying = [[e for e in range(len(cage_edges)) if on_segment(positions[pair], ends[e])] for pair in pairs]
    assert [parent for parent in parents] == [found[0] if found else -1 for found in lying]
    assert np.bincount(parents[parents >= 0], minlength=len(cage_edges)).tolist() == [2 ** levels] * len(cage_edges)


def test_plan_attributes():
    point, corner, face, edge, dropped = geometry.plan_attributes(
        [("Col", 'POINT', 'FLOAT_COLOR'), ("uv", 'CORNER', 'FLOAT2'), ("id", 'FACE', 'INT'),
         ("flag", 'EDGE', 'BOOLEAN'), ("count", 'POINT', 'INT'), (".select_vert", 'POINT', 'BOOLEAN'),
         ("position", 'POINT', 'FLOAT_VECTOR'), ("corner_id", 'CORNER', 'INT')], skip={"position"})
    assert [n for n, _, _ in point] == ["Col", "count"] and [n for n, _, _ in corner] == ["uv"]
    assert [n for n, _, _ in face] == ["id"] and [n for n, _, _ in edge] == ["flag"]
    assert [n for n, _, _ in dropped] == ["corner_id"]


def test_refined_values_back_to_their_type():
    refined = np.array([0.0, 0.25, 0.5001, 2.6, -1.4], np.float32)
    assert geometry.from_refined(refined, 'INT').tolist() == [0, 0, 1, 3, -1]
    assert geometry.from_refined(refined, 'BOOLEAN').tolist() == [False, True, True, True, False]
    assert geometry.from_refined(refined, 'FLOAT') is refined


def test_inherit_edge_values():
    parents = np.array([2, -1, 0, 2])
    assert geometry.inherit_edge_values(np.array([5, 6, 7]), parents).tolist() == [7, 0, 5, 7]
    assert geometry.inherit_edge_values(np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]]), parents).tolist() == [
        [5.0, 6.0], [0.0, 0.0], [1.0, 2.0], [5.0, 6.0]]


def test_options_keywords():
    assert settings.Options(rules='OPENSUBDIV', boundary='KEEP_CORNERS', crease_threshold=0.7).plan_keywords() == {
        "threads": settings.THREADS, "rules": "opensubdiv", "boundary": "edges-and-corners", "crease_threshold": 0.0,
        "limit_surface": True, "uv_interpolation": "boundaries"}
    assert settings.Options(crease_threshold=0.7, use_limit_surface=False, uv_smooth='NONE').plan_keywords() == {
        "threads": settings.THREADS, "rules": "hoppe94", "boundary": "edges", "crease_threshold": pytest.approx(0.7),
        "limit_surface": False, "uv_interpolation": "all"}


def test_uv_smooth_is_blenders_mapping():
    # BKE_subdiv_fvar_interpolation_from_uv_smooth: None is linear everywhere, All smooth everywhere.
    uv_smooth = {choice.identifier: choice.core for choice in settings.BY_NAME["uv_smooth"].choices}
    assert uv_smooth == {
        'NONE': "all", 'PRESERVE_CORNERS': "corners", 'PRESERVE_CORNERS_AND_JUNCTIONS': "corners-plus1",
        'PRESERVE_CORNERS_JUNCTIONS_AND_CONCAVE': "corners-plus2", 'PRESERVE_BOUNDARIES': "boundaries",
        'SMOOTH_ALL': "none"}
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    for smooth in uv_smooth:
        options = settings.Options(rules='OPENSUBDIV', uv_smooth=smooth)
        plan = _loopsub.Plan(triangles, 4, 1, face_varying_indices=[triangles], **options.plan_keywords())
        assert plan.uv_interpolation == uv_smooth[smooth] and plan.limit_surface


def test_options_are_the_settings_of_one_subdivision():
    options = settings.Options()
    assert not {"render_levels", "render_dicing_rate", "store_result"} & set(vars(options))
    assert all(getattr(options, name) == settings.BY_NAME[name].default for name in settings.SUBDIVISION)
    assert all(setting.default in [choice.identifier for choice in setting.choices]
               for setting in settings.SETTINGS if setting.choices)


def test_shared_positions():
    positions = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1], [1, 1, 1]], np.float32)
    assert geometry.shared_positions(positions) == 1
    assert geometry.shared_positions(positions[:4]) == 0
    # Three at one place are two extra; -0.0 is where 0.0 is; equal x and y alone are not the same place.
    positions = np.array([[0, 2, 3], [-0.0, 2, 3], [0, 2, 3], [0, 2, 4], [5, 6, 7]], np.float32)
    assert geometry.shared_positions(positions) == 2
    assert geometry.shared_positions(positions[2:]) == 0


def test_shared_vertex_normals():
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    up = np.tile(np.array([0, 0, 1], np.float32), (2, 3, 1))
    shared = geometry.shared_vertex_normals(triangles, up, 5)
    assert shared.shape == (5, 3) and np.array_equal(shared[:4], np.tile([0, 0, 1], (4, 1))) and not shared[4].any()
    split = up.copy()
    split[1, 0] = (0, 1, 0)  # vertex 1 gets another normal in the second triangle: a crease
    assert geometry.shared_vertex_normals(triangles, split, 5) is None


def _grid_triangles(cuts):
    """A flat grid of cuts x cuts squares, two triangles each: ((cuts + 1)^2, 3) positions and its triangles."""
    side = cuts + 1
    positions = np.array([(x, y, 0.0) for y in range(side) for x in range(side)], np.float32)
    corners = np.array([y * side + x for y in range(cuts) for x in range(cuts)], np.int32)
    triangles = np.concatenate([np.stack([corners, corners + 1, corners + side + 1], axis=1),
                                np.stack([corners, corners + side + 1, corners + side], axis=1)])
    return positions, triangles


def test_an_open_grid_has_one_limit_normal_per_vertex_and_a_crease_splits_them():
    """What Source.vertex_normals relies on: without a crease every corner takes its vertex's row (a boundary
    vertex's fan is one side, whose normal is its own), and the rows are the per-corner normals; a crease through the
    grid gives its vertices rows per side."""
    positions, triangles = _grid_triangles(4)
    positions[:, 2] = 0.2 * np.sin(positions[:, 0]) * np.cos(positions[:, 1])
    plan = _loopsub.Plan(triangles, len(positions), 2, rules="opensubdiv", limit_surface=True)
    _, compact = plan.evaluate_with_limit_normals(positions)
    _, per_corner = plan.evaluate_with_normals(positions)
    assert plan.num_limit_normals == plan.num_output_vertices
    assert np.array_equal(plan.corner_normal_indices, plan.triangles)
    assert np.array_equal(compact[plan.triangles], per_corner)
    middle = np.flatnonzero(positions[:, 0] == 2)
    creased = _loopsub.Plan(triangles, len(positions), 1, rules="opensubdiv", limit_surface=True,
                            crease_edges=np.stack([middle[:-1], middle[1:]], axis=1).astype(np.int32),
                            crease_sharpness=np.full(len(middle) - 1, 10.0, np.float32))
    assert creased.num_limit_normals > creased.num_output_vertices


def test_every_choice_names_an_option_of_the_core():
    core = _loopsub.option_names()
    for keyword, setting in (("rules", "rules"), ("boundary", "boundary"), ("uv_interpolation", "uv_smooth")):
        assert {choice.core for choice in settings.BY_NAME[setting].choices} <= set(core[keyword])
    # The dicing measures are screen_space_rates' own: each is accepted, and they differ.
    square = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0.5]], np.float32)
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    camera = np.array([[2, 0, 0, 0], [0, 2, 0, 0], [0, 0, -1, 4], [0, 0, -1, 5]], np.float32)
    rates = {choice.identifier: _loopsub.screen_space_rates(
        square, triangles, camera, (500, 500), **settings.Options(dicing_measure=choice.identifier,
                                                                  dicing_rate=1.0).rate_keywords())[1].tolist()
             for choice in settings.BY_NAME["dicing_measure"].choices}
    assert rates['LENGTH'] != rates['DEVIATION']


def test_tessellation_keywords_build_a_tessellation():
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    options = settings.Options(rules='OPENSUBDIV', boundary='KEEP_CORNERS', use_adaptive=True)
    tessellation = _loopsub.Tessellation(triangles, 4, 3, **options.tessellation_keywords())
    assert tessellation.num_points == 16 and len(tessellation.triangles) == 18


def _tessellated_square(rates):
    """A unit square of two triangles tessellated at rates (per edge: (0,1), (1,3), (3,2), (2,0), (1,2)), its points
    placed linearly (so that each lies where its parameters say, in the plane)."""
    square = np.array([[0, 0], [1, 0], [0, 1], [1, 1]], np.float32)
    triangles = np.array([[0, 1, 2], [1, 3, 2]], np.int32)
    edges = np.array([[0, 1], [1, 3], [3, 2], [2, 0], [1, 2]], np.int32)
    tessellation = _loopsub.Tessellation(triangles, 4, edges=edges, edge_rates=np.array(rates, np.int32))
    corner_parameters = tessellation.face_point_parameters[tessellation.corner_face_points]
    corners = geometry.interpolate_in_triangles(square[triangles], np.repeat(tessellation.parent_triangles, 3),
                                                corner_parameters.reshape(-1, 2)).reshape(-1, 3, 2)
    return square, triangles, edges, tessellation, corner_parameters, corners


def test_tessellated_edges_find_the_cage_edge_they_lie_on():
    square, triangles, edges, tessellation, corner_parameters, corners = _tessellated_square([2, 3, 1, 4, 5])
    # The same points by the tessellation's own numbering: each point's place is the same from every triangle.
    placed = np.zeros((tessellation.num_points, 2), np.float32)
    placed[tessellation.triangles.ravel()] = corners.reshape(-1, 2)
    assert np.abs(placed[tessellation.triangles] - corners).max() < 1e-6
    out_edges, triangle_edges = tessellation.output_edges()
    sides = geometry.tessellated_edge_sides(tessellation.corner_face_points, tessellation.face_point_parameters)
    side_edges = geometry.lookup_edges(edges, triangles[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), 4).reshape(-1, 3)
    parents = geometry.tessellated_edge_parents(triangle_edges, sides, tessellation.parent_triangles, side_edges,
                                                len(out_edges))
    # Checked against the square's geometry: an edge lies on the cage edge it names (both ends on its segment), and
    # on none when it names none; each cage edge is cut into its rate.
    for edge, parent in zip(out_edges, parents):
        a, b = placed[edge]
        lying = [e for e, (p, q) in enumerate(square[edges])
                 if all(abs((q - p)[0] * (x - p)[1] - (q - p)[1] * (x - p)[0]) < 1e-6 for x in (a, b))]
        assert parent == (lying[0] if lying else -1)
    assert np.bincount(parents[parents >= 0], minlength=5).tolist() == [2, 3, 1, 4, 5]


def test_interpolate_in_triangles_is_linear():
    corner_values = np.array([[[0, 0, 1], [2, 0, 1], [0, 4, 1]]], np.float32)
    values = geometry.interpolate_in_triangles(corner_values, np.array([0, 0, 0]),
                                               np.array([[0, 0], [0.5, 0.5], [0.25, 0.25]], np.float32))
    assert np.allclose(values, [[0, 0, 1], [1, 2, 1], [0.5, 1, 1]])


def test_limit_crease_weights():
    assert geometry.limit_crease_weights(np.array([10.0, 3.6, 0.1], np.float32), 'OPENSUBDIV').tolist() == [1, 0, 0]
    assert geometry.limit_crease_weights(np.array([1.0, 0.6], np.float32), 'HOPPE94').tolist() == pytest.approx(
        [1.0, 0.6])
