"""Every class of bad input raises a clear Python exception (never a crash, never a silent conversion)."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import _loopsub
from conftest import tetrahedron


@pytest.fixture
def mesh():
    return tetrahedron()


def still_works():
    """After an error the module (and a new plan) behave normally."""
    p, t = tetrahedron()
    np.testing.assert_allclose(_loopsub.subdivide(p, t, 1)["positions"][0], p[0] / 4, atol=1e-6)


# ---------------------------------------------------------------------------------------------------------------
# Mesh content


@pytest.mark.parametrize("bad_index", [4, 1000, -1])
def test_index_out_of_range(mesh, bad_index):
    p, t = mesh
    t = t.copy()
    t[2, 1] = bad_index
    with pytest.raises(ValueError, match=str(bad_index)):
        _loopsub.subdivide(p, t, 1)
    with pytest.raises(ValueError, match=str(bad_index)):
        _loopsub.Plan(t, 4)
    still_works()


@pytest.mark.parametrize("triangle", [[0, 0, 1], [2, 1, 2], [3, 3, 3]])
def test_degenerate_triangle(mesh, triangle):
    p, t = mesh
    t = np.vstack([t, [triangle]]).astype(np.int32)
    with pytest.raises(ValueError):
        _loopsub.subdivide(p, t, 1)
    still_works()


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_positions(mesh, value):
    p, t = mesh
    p = p.copy()
    p[3, 1] = value
    with pytest.raises(ValueError):
        _loopsub.subdivide(p, t, 1)
    plan = _loopsub.Plan(t, 4)
    with pytest.raises(ValueError):
        plan.evaluate(p)
    # The plan stays usable after the refused evaluation.
    np.testing.assert_allclose(plan.evaluate(tetrahedron()[0])[0], tetrahedron()[0][0] / 4, atol=1e-6)


@pytest.mark.parametrize("value", [np.nan, np.inf])
def test_non_finite_vertex_data_and_face_varying(mesh, value):
    p, t = mesh
    data = np.ones((4, 2), np.float32)
    data[1, 1] = value
    with pytest.raises(ValueError):
        _loopsub.subdivide(p, t, 1, vertex_data=data)
    uv = np.zeros((4, 3, 2), np.float32)
    uv[3, 2, 1] = value
    with pytest.raises(ValueError, match=r"face_varying: triangle 3, corner 2 \(face-varying layer 0\) has a "
                                         r"non-finite value \((nan|inf)\) in channel 1"):
        _loopsub.subdivide(p, t, 1, face_varying=uv)


@pytest.mark.parametrize("argument,bad", [
    ("crease_edges", [[0, 4]]),
    ("crease_edges", [[-1, 0]]),
    ("corner_vertices", [9]),
    ("cone_vertices", [4]),
])
def test_tag_index_out_of_range(mesh, argument, bad):
    p, t = mesh
    with pytest.raises(ValueError):
        _loopsub.subdivide(p, t, 1, **{argument: np.array(bad, np.int32)})
    still_works()


@pytest.mark.parametrize("sharpness", [-1.0, np.nan, np.inf])
def test_bad_sharpness_values(mesh, sharpness):
    p, t = mesh
    with pytest.raises(ValueError):
        _loopsub.subdivide(p, t, 1, rules="opensubdiv", crease_edges=np.array([[0, 1]], np.int32),
                           crease_sharpness=np.array([sharpness], np.float32))
    with pytest.raises(ValueError):
        _loopsub.subdivide(p, t, 1, rules="opensubdiv", corner_vertices=np.array([0], np.int32),
                           corner_sharpness=np.array([sharpness], np.float32))


# ---------------------------------------------------------------------------------------------------------------
# Array types and layouts: never converted


@pytest.mark.parametrize("dtype", [np.float64, np.float16, np.int32])
def test_positions_wrong_dtype(mesh, dtype):
    p, t = mesh
    with pytest.raises(TypeError) as e:
        _loopsub.subdivide(p.astype(dtype), t)
    assert "positions" in str(e.value) and "float32" in str(e.value) and np.dtype(dtype).name in str(e.value)


@pytest.mark.parametrize("dtype", [np.int64, np.uint32, np.int16, np.float32])
def test_triangles_wrong_dtype(mesh, dtype):
    p, t = mesh
    with pytest.raises(TypeError) as e:
        _loopsub.subdivide(p, t.astype(dtype))
    assert "triangles" in str(e.value) and "int32" in str(e.value) and np.dtype(dtype).name in str(e.value)
    with pytest.raises(TypeError, match="triangles"):
        _loopsub.Plan(t.astype(dtype), 4)


def test_byte_swapped_float32_is_refused(mesh):
    p, t = mesh
    with pytest.raises(TypeError, match="positions"):
        _loopsub.subdivide(p.astype(">f4"), t)


def test_not_an_array(mesh):
    p, t = mesh
    with pytest.raises(TypeError, match="positions must be a numpy.ndarray.*list"):
        _loopsub.subdivide(p.tolist(), t)
    with pytest.raises(TypeError, match="triangles must be a numpy.ndarray.*tuple"):
        _loopsub.Plan(tuple(map(tuple, t.tolist())), 4)


@pytest.mark.parametrize("shape", [(4, 2), (4, 4), (12,), (4, 3, 1)])
def test_positions_wrong_shape(mesh, shape):
    p, t = mesh
    with pytest.raises(ValueError) as e:
        _loopsub.subdivide(np.zeros(shape, np.float32), t)
    assert "positions" in str(e.value) and "(N, 3)" in str(e.value) and str(shape) in str(e.value)


@pytest.mark.parametrize("shape", [(4, 4), (12,), (4, 2)])
def test_triangles_wrong_shape(mesh, shape):
    p, _ = mesh
    with pytest.raises(ValueError, match=r"triangles must have shape \(M, 3\)"):
        _loopsub.subdivide(p, np.zeros(shape, np.int32))


def test_non_contiguous_inputs(mesh):
    p, t = mesh
    wide = np.zeros((4, 6), np.float32)
    wide[:, ::2] = p
    strided = wide[:, ::2]
    assert strided.shape == (4, 3) and not strided.flags.c_contiguous
    with pytest.raises(ValueError, match="positions must be C-contiguous"):
        _loopsub.subdivide(strided, t)
    with pytest.raises(ValueError, match="triangles must be C-contiguous"):
        _loopsub.subdivide(p, np.asfortranarray(t))
    plan = _loopsub.Plan(t, 4)
    with pytest.raises(ValueError, match="values must be C-contiguous"):
        plan.evaluate(strided)
    with pytest.raises(ValueError, match="crease_edges must be C-contiguous"):
        _loopsub.Plan(t, 4, crease_edges=np.array([[0, 1], [1, 2]], np.int32).T.copy().T)


def test_unaligned_input(mesh):
    p, t = mesh
    raw = np.zeros(p.nbytes + 1, np.uint8)
    unaligned = np.frombuffer(raw.data, dtype=np.float32, count=p.size, offset=1).reshape(4, 3)
    if unaligned.flags.aligned:
        pytest.skip("numpy considers this buffer aligned on this platform")
    with pytest.raises(ValueError, match="aligned"):
        _loopsub.Plan(t, 4).evaluate(unaligned)


def test_evaluate_values_wrong_rows_or_rank(mesh):
    p, t = mesh
    plan = _loopsub.Plan(t, 4)
    with pytest.raises(ValueError, match=r"values must have shape \(N=4, C\) or \(N=4,\), got \(5, 3\)"):
        plan.evaluate(np.zeros((5, 3), np.float32))
    with pytest.raises(ValueError):
        plan.evaluate(np.zeros((4, 3, 1), np.float32))
    with pytest.raises(TypeError, match="float32"):
        plan.evaluate(p.astype(np.float64))
    with pytest.raises(ValueError, match=r"\(T=4, 3, C\)"):
        plan.evaluate_face_varying(np.zeros((5, 3, 2), np.float32))
    with pytest.raises(ValueError):
        plan.evaluate_face_varying(np.zeros((4, 2, 2), np.float32))


def test_bad_out(mesh):
    p, t = mesh
    plan = _loopsub.Plan(t, 4)
    n = plan.num_output_vertices
    with pytest.raises(ValueError, match=r"out must have shape \(N_out=10, C=3\), got \(9, 3\)"):
        plan.evaluate(p, out=np.zeros((n - 1, 3), np.float32))
    with pytest.raises(ValueError, match="out must have shape"):
        plan.evaluate(p, out=np.zeros((n,), np.float32))  # 2-D values need a 2-D out
    with pytest.raises(TypeError, match="out must have dtype float32, got float64"):
        plan.evaluate(p, out=np.zeros((n, 3), np.float64))
    read_only = np.zeros((n, 3), np.float32)
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match="out must be writeable"):
        plan.evaluate(p, out=read_only)
    with pytest.raises(ValueError, match="out must be C-contiguous"):
        plan.evaluate(p, out=np.zeros((n, 6), np.float32)[:, ::2])
    # The output overlapping the input would be overwritten while it is read.
    shared = np.zeros((n, 3), np.float32)
    shared[:4] = p
    with pytest.raises(ValueError, match="share memory"):
        plan.evaluate(shared[:4], out=shared)
    with pytest.raises(ValueError, match="out must have shape"):
        plan.evaluate_face_varying(np.zeros((4, 3, 2), np.float32), out=np.zeros((16, 3, 3), np.float32))


# ---------------------------------------------------------------------------------------------------------------
# Options


@pytest.mark.parametrize("levels", [-1, -5])
def test_negative_levels(mesh, levels):
    p, t = mesh
    with pytest.raises(ValueError, match="levels"):
        _loopsub.subdivide(p, t, levels)
    with pytest.raises(ValueError, match="levels"):
        _loopsub.Plan(t, 4, levels)


@pytest.mark.parametrize("options,match", [
    (dict(rules="loop"), "rules must be 'hoppe94' or 'opensubdiv', got 'loop'"),
    (dict(boundary="sideways"), "boundary"),
    (dict(uv_interpolation="linear"), "uv_interpolation"),
    (dict(crease_method="linear"), "crease_method"),
    (dict(threads=0), "threads"),
    (dict(threads=257), "threads must be between 1 and 256, got 257"),  # not 257 threads started
    (dict(threads=2**31 - 1), "threads must be between 1 and 256"),
    (dict(memory_limit_bytes=-1), "memory_limit_bytes"),
    (dict(crease_threshold=float("nan")), "crease_threshold"),
    (dict(crease_sharpness=np.ones(1, np.float32)), "without crease_edges"),
    (dict(corner_sharpness=np.ones(1, np.float32)), "without corner_vertices"),
    (dict(crease_edges=np.array([[0, 1]], np.int32), crease_sharpness=np.ones(2, np.float32)), r"\(K=1,\)"),
    (dict(corner_vertices=np.array([0, 1], np.int32), corner_sharpness=np.ones(1, np.float32)), r"\(K=2,\)"),
])
def test_bad_options(mesh, options, match):
    p, t = mesh
    with pytest.raises(ValueError, match=match):
        _loopsub.subdivide(p, t, 1, **options)


def test_num_vertices_must_cover_the_indices(mesh):
    _, t = mesh
    with pytest.raises(ValueError):
        _loopsub.Plan(t, 3)
    with pytest.raises(ValueError):
        _loopsub.Plan(t, -1)


def test_memory_limit_raises_memory_error_with_the_size(mesh):
    p, t = mesh
    with pytest.raises(MemoryError) as e:
        _loopsub.subdivide(p, t, 6, memory_limit_bytes=100_000)
    required = e.value.required_bytes
    assert required > 100_000
    assert str(required) in str(e.value)
    # The limit is what decides: exactly the required size is enough.
    plan = _loopsub.Plan(t, 4, 6, memory_limit_bytes=required)
    assert plan.num_output_triangles == 4 * 4**6
    with pytest.raises(MemoryError):
        _loopsub.Plan(t, 4, 6, memory_limit_bytes=required - 1)


@pytest.mark.parametrize("levels", [14, 20, 31, 40, 64])
def test_absurd_levels_hit_the_default_limit(mesh, levels):
    """4 * 4**levels triangles would overflow any counter: the estimate must say no, not wrap around."""
    p, t = mesh
    with pytest.raises(MemoryError) as e:
        _loopsub.subdivide(p, t, levels)
    assert e.value.required_bytes > 4 << 30
    still_works()


@pytest.mark.parametrize("triangles", [np.zeros((0, 3), np.int32), tetrahedron()[1]])
@pytest.mark.parametrize("levels", [65, 1000])
def test_levels_past_64_are_refused(triangles, levels):
    """A mesh without triangles refines to itself at any level, but each level is a record of the plan: 2**31 - 1
    of them took all of the machine's memory before this check (found by test_hostile_arguments)."""
    with pytest.raises(ValueError, match=f"levels must be between 0 and 64, got {levels}"):
        _loopsub.Plan(triangles, 4, levels)
    with pytest.raises(ValueError, match="levels must be between 0 and 64"):
        _loopsub.subdivide(np.zeros((4, 3), np.float32), triangles, levels)


# Runs in a child process capped at 2 GiB of address space (under the sanitizer, whose shadow memory needs terabytes
# of it, at 2 GiB per allocation instead): if the size check is wrong, the core's allocations fail there
# (std::bad_alloc, a MemoryError *without* required_bytes) instead of exhausting the shared machine.
_HUGE_LEVELS_CHILD = textwrap.dedent("""
    import os, resource, sys
    import numpy as np
    import _loopsub
    if "asan" not in os.environ.get("LD_PRELOAD", ""):
        resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
    t = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], np.int32)
    try:
        _loopsub.Plan(t, 4, int(sys.argv[1]), memory_limit_bytes=2**63 - 1)
    except MemoryError as e:
        print("required_bytes" if hasattr(e, "required_bytes") else "allocator: " + str(e))
    else:
        print("built")
""")


@pytest.mark.parametrize("levels", [
    16,  # 4**17 triangles: past the int32 indices, far below the limit
    31,  # 4**32 triangles: past 64 bits, which must saturate rather than wrap around
    40,
])
def test_absurd_levels_are_refused_even_with_no_memory_limit(levels):
    """With the limit out of the way the count check must still refuse, before allocating anything."""
    env = dict(os.environ, PYTHONPATH=os.path.dirname(_loopsub.__file__))
    env["ASAN_OPTIONS"] = env.get("ASAN_OPTIONS", "") + ":max_allocation_size_mb=2048:allocator_may_return_null=1"
    child = subprocess.run([sys.executable, "-c", _HUGE_LEVELS_CHILD, str(levels)], env=env, capture_output=True,
                           text=True, timeout=120)
    assert child.returncode == 0, child.stderr
    assert child.stdout.strip() == "required_bytes"


@pytest.fixture
def one_layer_plan(mesh):
    """A plan of the tetrahedron with one face-varying layer of 12 values (one per corner)."""
    _, t = mesh
    return _loopsub.Plan(t, 4, 1, face_varying_indices=[np.arange(12, dtype=np.int32).reshape(4, 3)])


@pytest.mark.parametrize("layer", [-1, 1, 2**40, -(2**70), np.int64(5)])
def test_layer_out_of_range(one_layer_plan, layer):
    plan = one_layer_plan
    values = np.zeros((12, 2), np.float32)
    with pytest.raises(ValueError, match=f"layer {int(layer)} is not a face-varying layer of this Plan \\(it has 1\\)"):
        plan.evaluate_face_varying(values, layer=layer)
    with pytest.raises(ValueError, match=f"layer {int(layer)} is not"):
        plan.face_varying_indices(layer)
    # A numpy integer is an index like any other.
    np.testing.assert_array_equal(plan.evaluate_face_varying(values, layer=np.int32(0)),
                                  plan.evaluate_face_varying(values, layer=0))


@pytest.mark.parametrize("layer", ["0", 0.5, [0]])
def test_layer_not_an_integer(one_layer_plan, layer):
    plan = one_layer_plan
    with pytest.raises(TypeError, match="layer must be an integer, got (str|float|list)"):
        plan.evaluate_face_varying(np.zeros((12, 2), np.float32), layer=layer)
    with pytest.raises(TypeError, match="layer must be an integer"):
        plan.face_varying_indices(layer)
