"""Generated hostile arguments (Hypothesis): every call into the module either gives a valid result or raises one of
its documented exceptions (TypeError, ValueError, IndexError, MemoryError). It never crashes: a crash in the native
module takes the artist's Blender session down with it.

The arguments start from a small random mesh and its options, each argument replaced at random by something hostile:
a wrong dtype, shape, stride, byte order or type, a read-only or aliased output, indices out of range, degenerate or
non-manifold triangles, NaN, infinite and huge values, out-of-range levels, layers and options. scripts/test.sh runs
this file again in the sanitizer build (ASan + UBSan, build-asan/), where a read out of bounds fails it too.
LOOPSUB_HOSTILE_EXAMPLES sets the number of examples per test (default 150, a fixed sequence); a larger number also
draws new ones on every run.
"""
import os
import resource

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import _loopsub

EXAMPLES = int(os.environ.get("LOOPSUB_HOSTILE_EXAMPLES", "150"))
DOCUMENTED = (TypeError, ValueError, IndexError, MemoryError)  # docs/python.md, "Errors"
hostile = settings(max_examples=EXAMPLES, deadline=None, database=None, derandomize=EXAMPLES <= 150,
                   suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

# Values a float argument may hold: ordinary ones mostly, and what breaks arithmetic.
FLOATS = st.one_of(st.floats(-4, 4, width=32),
                   st.sampled_from([0.0, -0.0, 1e-45, 1e30, -1e38, 3.4028235e38, np.inf, -np.inf, np.nan]))
NOT_ARRAYS = st.sampled_from([None, 3, 2.5, "x", [[0, 1, 2]], (), object()])


def corrupt(draw, array):
    """The array, or most of the time one hostile variant of it."""
    how = draw(st.sampled_from(["keep"] * 4 + ["dtype", "shape", "stride", "byteswap", "readonly", "not-array",
                                                "empty", "scalar", "transpose"]))
    if how == "dtype":
        with np.errstate(all="ignore"):
            return array.astype(draw(st.sampled_from([np.float64, np.float16, np.int64, np.int32, np.uint32,
                                                      np.uint8, np.bool_, np.complex64, object])))
    if how == "shape":
        return np.resize(array, draw(st.lists(st.integers(0, 12), min_size=1, max_size=3)))
    if how == "stride":
        return np.repeat(array, 2, axis=0)[::2]
    if how == "byteswap":
        return array.byteswap().view(array.dtype.newbyteorder())
    if how == "readonly":
        array = array.copy()
        array.setflags(write=False)
        return array
    if how == "not-array":
        return draw(NOT_ARRAYS)
    if how == "empty":
        return array[:0]
    if how == "scalar":
        return np.array(array.flat[0] if array.size else 0, array.dtype)
    if how == "transpose":
        return array.T
    return array


@st.composite
def meshes(draw):
    """Triangles over n vertices, mostly valid; some indices out of range, repeated or shared by many faces."""
    n = draw(st.integers(0, 9))
    index = st.one_of(st.integers(0, max(n - 1, 0)), st.sampled_from([-1, n, 2**31 - 1, -(2**31)]))
    m = draw(st.integers(0, 10))
    triangles = np.array(draw(st.lists(st.tuples(index, index, index), min_size=m, max_size=m)),
                         np.int32).reshape(-1, 3)
    positions = np.array(draw(st.lists(st.tuples(FLOATS, FLOATS, FLOATS), min_size=n, max_size=n)),
                         np.float32).reshape(-1, 3)
    if draw(st.booleans()):  # half the time all finite, so that the rest of the call is reached
        positions = np.nan_to_num(positions, nan=0.0, posinf=1.0, neginf=-1.0)
    return positions, triangles


@st.composite
def options(draw, num_vertices, num_triangles):
    """A random subset of the options, each ordinary or hostile."""
    vertex = st.one_of(st.integers(0, max(num_vertices - 1, 0)), st.sampled_from([-1, num_vertices, 2**31 - 1]))
    def indices(width):  # (k, width) vertex indices; (k,) for width 1
        k = draw(st.integers(0, 4))
        rows = np.array(draw(st.lists(st.tuples(*[vertex] * width), min_size=k, max_size=k)), np.int32)
        rows = rows.reshape(k, width)
        return rows if width > 1 else rows.reshape(k)
    def sharpness(k):
        return np.array(draw(st.lists(FLOATS, min_size=k, max_size=k)), np.float32)
    crease_edges = indices(2)
    corner_vertices = indices(1)
    choices = {
        "rules": st.sampled_from(["hoppe94", "opensubdiv", "loop", ""]),
        "crease_edges": st.just(crease_edges),
        "crease_sharpness": st.sampled_from([sharpness(len(crease_edges)), sharpness(len(crease_edges) + 1)]),
        "corner_vertices": st.just(corner_vertices),
        "corner_sharpness": st.just(sharpness(len(corner_vertices))),
        "cone_vertices": st.just(indices(1)),
        "crease_threshold": FLOATS,
        "boundary": st.sampled_from(["edges", "edges-and-corners", "none", "all"]),
        "crease_method": st.sampled_from(["uniform", "chaikin", "smooth"]),
        "threads": st.sampled_from([1, 2, 3, 0, -1, 257, 2**31 - 1]),
        "scalar": st.booleans(),
        "memory_limit_bytes": st.sampled_from([0, 1, 1000, 1 << 20, -1, 2**62, 2**63 - 1]),
        "limit_surface": st.booleans(),
        "uv_interpolation": st.sampled_from(["none", "corners", "corners-plus1", "corners-plus2", "boundaries",
                                             "all", "some"]),
        "hole_triangles": st.just(np.array(draw(st.lists(st.integers(-1, num_triangles), max_size=3)), np.int32)),
        "level_tables": st.sampled_from(["auto", "stored", "derived", "fast"]),
    }
    chosen = draw(st.lists(st.sampled_from(sorted(choices)), unique=True, max_size=6))
    result = {}
    for name in chosen:
        value = draw(choices[name])
        result[name] = corrupt(draw, value) if isinstance(value, np.ndarray) else value
    return result


@pytest.fixture(autouse=True)
def bounded_address_space():
    """An allocation nobody planned (the core checks every size against memory_limit_bytes first) fails here as a
    MemoryError without required_bytes, a test failure, instead of taking the machine's memory. Under the sanitizer,
    whose shadow memory needs terabytes of address space, its own cap per allocation stands in
    (tests/CMakeLists.txt)."""
    if "asan" in os.environ.get("LD_PRELOAD", ""):
        yield
        return
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (8 << 30, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))


def refused(error):
    """A documented refusal: not a MemoryError from an allocation that failed without the size check."""
    if isinstance(error, MemoryError):
        assert hasattr(error, "required_bytes"), f"an allocation failed unchecked: {error!r}"


LEVELS = st.one_of(st.integers(0, 3), st.sampled_from([-1, 4, 40, 2**31 - 1]))


def check_refined(positions, triangles, num_vertices):
    """What a caller relies on from a result: finite positions and triangles that index them."""
    assert positions.dtype == np.float32 and positions.shape == (num_vertices, 3)
    assert np.isfinite(positions).all(), "non-finite output from a call that did not raise"
    assert triangles.dtype == np.int32 and triangles.ndim == 2 and triangles.shape[1] == 3
    if triangles.size:
        assert triangles.min() >= 0 and triangles.max() < num_vertices


@hostile
@given(data=st.data())
def test_subdivide_gives_a_valid_result_or_a_documented_error(data):
    positions, triangles = data.draw(meshes())
    kwargs = data.draw(options(len(positions), len(triangles)))
    if data.draw(st.booleans()):
        kwargs["vertex_data"] = corrupt(data.draw, np.ones((len(positions), 2), np.float32))
    if data.draw(st.booleans()):
        uvs = np.array(data.draw(st.lists(FLOATS, min_size=6 * len(triangles), max_size=6 * len(triangles))),
                       np.float32).reshape(len(triangles), 3, 2)
        kwargs["face_varying"] = data.draw(st.sampled_from([corrupt(data.draw, uvs), {"UVMap": corrupt(data.draw, uvs)},
                                                            {3: uvs}, [uvs]]))
    args = (corrupt(data.draw, positions), corrupt(data.draw, triangles), data.draw(LEVELS))
    try:
        result = _loopsub.subdivide(*args, **kwargs)
    except DOCUMENTED as error:
        refused(error)
        return
    plan = result["plan"]
    check_refined(result["positions"], result["triangles"], plan.num_output_vertices)


@st.composite
def plans(draw):
    """A plan that builds: a small closed or open mesh with a UV layer, random rules and settings."""
    n = draw(st.integers(3, 6))
    ring = [(0, i, i % n + 1) for i in range(1, n + 1)]  # a fan around vertex 0: an open disk
    triangles = np.array(ring + ([(n + 1, (i % n) + 1, i) for i in range(1, n + 1)] if draw(st.booleans()) else []),
                         np.int32)
    num_vertices = int(triangles.max()) + 1
    uv_indices = np.arange(triangles.size, dtype=np.int32).reshape(-1, 3) % draw(st.integers(1, triangles.size))
    plan = _loopsub.Plan(triangles, num_vertices, draw(st.integers(0, 3)),
                         rules=draw(st.sampled_from(["hoppe94", "opensubdiv"])),
                         limit_surface=draw(st.booleans()), threads=draw(st.sampled_from([1, 2])),
                         face_varying_indices=[uv_indices] if draw(st.booleans()) else None)
    return plan, num_vertices, int(uv_indices.max()) + 1


@hostile
@given(data=st.data())
def test_plan_calls_give_a_valid_result_or_a_documented_error(data):
    plan, num_vertices, num_values = data.draw(plans())
    rows = st.sampled_from([num_vertices, num_values, num_vertices + 1, 0, plan.num_output_vertices])
    for _ in range(data.draw(st.integers(1, 4))):
        call = data.draw(st.sampled_from(["evaluate", "evaluate_with_normals", "evaluate_face_varying", "level_edges",
                                          "level_num_vertices", "level_vertex_types", "face_varying_indices"]))
        values = corrupt(data.draw, np.array(data.draw(st.lists(FLOATS, min_size=3 * 12, max_size=3 * 12)),
                                             np.float32).reshape(12, 3)[:data.draw(rows)])
        out = data.draw(st.sampled_from([None, "fresh", "aliased", "small"]))
        if out == "fresh":
            out = corrupt(data.draw, np.empty((plan.num_output_vertices, 3), np.float32))
        elif out == "aliased":
            out = values
        elif out == "small":
            out = np.empty((1, 3), np.float32)
        index = data.draw(st.one_of(st.integers(-1, 4), st.sampled_from([2**31 - 1, -(2**31), 2**40])))
        try:
            if call == "evaluate":
                result = plan.evaluate(values, out=out)
                assert result.shape[0] == plan.num_output_vertices
            elif call == "evaluate_with_normals":
                limit, normals = plan.evaluate_with_normals(values, out=out)
                assert limit.shape[0] == plan.num_output_vertices
                assert normals.shape == (plan.num_output_triangles, 3, 3) and np.isfinite(normals).all()
            elif call == "evaluate_face_varying":
                layer = data.draw(st.sampled_from([None, index]))
                result = plan.evaluate_face_varying(values, out=out, layer=layer)
                if np.isfinite(values).all():
                    assert np.isfinite(result).all()
            elif call == "level_edges":
                edges = plan.level_edges(index)
                assert edges.min(initial=0) >= 0 and edges.max(initial=-1) < plan.level_num_vertices(index)
            elif call == "level_num_vertices":
                assert plan.level_num_vertices(index) >= 0
            elif call == "level_vertex_types":
                assert len(plan.level_vertex_types(index)) == plan.level_num_vertices(index)
            else:
                indices = plan.face_varying_indices(index)
                assert indices.shape == (plan.num_output_triangles, 3) and indices.min(initial=0) >= 0
        except DOCUMENTED as error:
            refused(error)
    # After whatever was refused, the plan still evaluates.
    positions = np.random.default_rng(0).standard_normal((num_vertices, 3)).astype(np.float32)
    refined = plan.evaluate_with_normals(positions)[0] if plan.limit_surface else plan.evaluate(positions)
    check_refined(refined, plan.triangles, plan.num_output_vertices)

