"""The GIL is released while the core runs, and a plan shared between threads stays correct."""
import sys
import threading

import numpy as np
import pytest

import _loopsub
from conftest import grid, tetrahedron


@pytest.fixture
def long_switch_interval():
    """A thread holding the GIL keeps it for up to this long before Python forces a switch. With it, a native
    call that does not release the GIL lets no other Python thread run at all while it works, and one that does
    lets the waiting thread in at once."""
    old = sys.getswitchinterval()
    sys.setswitchinterval(0.5)
    yield
    sys.setswitchinterval(old)


def test_python_runs_while_evaluate_writes_its_output(long_switch_interval):
    """Proof by observation, not by timing: the main thread samples `out` while a worker thread runs evaluate().
    With the GIL held through the native call, every sample would show `out` either untouched (all NaN) or
    finished; a partly written sample can only be taken while the core is mid-way, with the GIL released.
    Repeated a few times so that scheduling luck cannot fail it; nothing can make it pass falsely."""
    p, t = grid(120, height=0.1)
    plan = _loopsub.Plan(t, len(p), 3)
    values = np.ascontiguousarray(np.tile(p, 4))  # 12 channels: a slower evaluate on the same topology
    out = np.empty((plan.num_output_vertices, values.shape[1]), np.float32)
    rows = np.linspace(0, len(out) - 1, 4096).astype(np.int64)  # samples across the whole output

    for attempt in range(10):
        out.fill(np.nan)
        worker = threading.Thread(target=plan.evaluate, args=(values,), kwargs={"out": out})
        worker.start()
        samples = []
        while worker.is_alive():
            samples.append(out[rows, 0].copy())
        worker.join()
        final = out[rows, 0].copy()
        assert np.isfinite(final).all()
        if any(not np.isnan(s).all() and not np.array_equal(s, final) for s in samples):
            return
    raise AssertionError("never saw evaluate() part-way through in 10 attempts: is the GIL held during evaluate?")


def test_python_runs_while_a_plan_is_built(long_switch_interval):
    """The worker reads a counter just before and just after building a Plan while the main thread increments
    it. With the GIL held by the constructor, the main thread cannot run between the two reads (the switch
    interval is far longer than the few bytecodes around the call), so the counter cannot move."""
    p, t = grid(100)
    for attempt in range(5):
        counter = [0]
        seen = {}
        done = threading.Event()

        def build():
            seen["before"] = counter[0]
            _loopsub.Plan(t, len(p), 3)
            seen["after"] = counter[0]
            done.set()

        worker = threading.Thread(target=build)
        worker.start()
        while not done.is_set():
            counter[0] += 1
        worker.join()
        if seen["after"] > seen["before"]:
            return
    raise AssertionError("the main thread never ran while a Plan was built: is the GIL held?")


def test_concurrent_evaluations_of_one_plan_are_correct():
    """evaluate() runs without the GIL and the core's plan is not reentrant: calls on one plan from several
    threads must still each get the right answer (the module serialises them per plan)."""
    p, t = grid(60, height=0.2)
    plan = _loopsub.Plan(t, len(p), 3)
    inputs = [(p * np.float32(k + 1)).astype(np.float32) for k in range(4)]
    expected = [plan.evaluate(x) for x in inputs]
    errors = []

    def work(k):
        try:
            for _ in range(15):
                np.testing.assert_array_equal(plan.evaluate(inputs[k]), expected[k])
        except AssertionError as e:  # collected: an exception in a thread would not fail the test
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert not errors, errors[0]


def test_two_plans_evaluate_concurrently_with_correct_results():
    p, t = tetrahedron()
    plans = [_loopsub.Plan(t, 4, 4), _loopsub.Plan(t, 4, 4, rules="opensubdiv")]
    expected = [plan.evaluate(p) for plan in plans]
    results = [None, None]

    def work(k):
        results[k] = [plans[k].evaluate(p) for _ in range(50)]

    threads = [threading.Thread(target=work, args=(k,)) for k in range(2)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    for k in range(2):
        for r in results[k]:
            np.testing.assert_array_equal(r, expected[k])


def test_any_thread_count_gives_the_same_bits():
    """The add-on runs the core on every core the machine has (artists' machines have 8 to 64): plans, their limit
    normals and UV layers, and tessellations give the same bits whatever the count, more threads than cores too."""
    p, t = grid(40, seed=5, height=0.2)
    uv = np.ascontiguousarray(p[t][:, :, :2])
    indices, values = _loopsub.weld_corner_values(t, len(p), uv)
    reference = None
    for threads in (1, 2, 3, 5, 8):
        plan = _loopsub.Plan(t, len(p), 3, rules="opensubdiv", limit_surface=True, threads=threads,
                             uv_interpolation="boundaries", face_varying_indices=[indices])
        points, normals = plan.evaluate_with_limit_normals(p)
        uvs = plan.evaluate_face_varying(values, layer=0)
        tessellation = _loopsub.Tessellation(t, len(p), 7, rules="opensubdiv", threads=threads)
        tess_points, tess_normals = tessellation.evaluate(p)
        result = (points, normals, uvs, tess_points, tess_normals)
        if reference is None:
            reference = result
        for got, expected in zip(result, reference):
            assert np.array_equal(got, expected), f"{threads} threads"
