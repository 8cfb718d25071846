"""The add-on's memory check (addon/model/memory.py), loaded by path with plain Python: what the process may still
use, read from a fake /proc and /sys tree; the estimate of an update against the core's own and against measured
peaks; the report's wording."""
import importlib.util
import os

import numpy as np
import pytest

import _loopsub
from conftest import icosahedron

_PATH = os.path.join(os.path.dirname(__file__), "..", "..", "addon", "model", "memory.py")
_spec = importlib.util.spec_from_file_location("loop_subdivision_memory", _PATH)
memory = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(memory)

KB, MB, GB = 1 << 10, 1 << 20, 1 << 30
NO_V1_LIMIT = 9223372036854771712  # what cgroup v1 shows when no limit is set


class Tree:
    """A fake root with /proc and /sys files."""

    def __init__(self, root):
        self.root = str(root)

    def write(self, path, text):
        full = os.path.join(self.root, path)
        os.makedirs(os.path.dirname(full), exist_ok=True)
        with open(full, "w", encoding="utf-8") as file:
            file.write(text)

    def meminfo(self, available):
        self.write("proc/meminfo", f"MemTotal:       24000000 kB\nMemFree:          100000 kB\n"
                                   f"MemAvailable:   {available // KB:8d} kB\nBuffers:           1000 kB\n")

    def cgroups(self, *lines):
        self.write("proc/self/cgroup", "".join(line + "\n" for line in lines))

    def v1(self, path, limit, usage, inactive):
        base = "sys/fs/cgroup/memory" + path
        self.write(base + "/memory.limit_in_bytes", f"{limit}\n")
        self.write(base + "/memory.usage_in_bytes", f"{usage}\n")
        self.write(base + "/memory.stat", f"cache 0\ninactive_file 1\ntotal_cache 0\ntotal_inactive_file {inactive}\n")

    def v2(self, path, limit, current, inactive):
        base = "sys/fs/cgroup" + path
        self.write(base + "/memory.max", f"{limit}\n")
        self.write(base + "/memory.current", f"{current}\n")
        self.write(base + "/memory.stat", f"anon 0\nfile 0\nactive_file 5\ninactive_file {inactive}\n")


@pytest.fixture
def tree(tmp_path):
    return Tree(tmp_path)


# ---------------------------------------------------------------------------------------------------------------
# available_bytes


def test_meminfo_alone(tree):
    tree.meminfo(20 * GB)
    assert memory.meminfo_available(tree.root) == 20 * GB
    assert memory.available_bytes(tree.root) == 20 * GB


def test_v1_limit_with_its_reclaimable_cache(tree):
    """As on this machine: cgroup v1 with the memory controller on its own line, and an empty unified line."""
    tree.meminfo(20 * GB)
    tree.cgroups("9:name=systemd:/", "4:memory:/process_api/abc", "1:cpu:/", "0::/")
    tree.v1("/process_api/abc", 2 * GB, 1536 * MB, 100 * MB)
    tree.v1("/process_api", NO_V1_LIMIT, 3 * GB, 0)
    tree.v1("", NO_V1_LIMIT, 8 * GB, 0)
    assert memory.cgroup_v1_available(tree.root) == 2 * GB - 1536 * MB + 100 * MB
    assert memory.cgroup_v2_available(tree.root) is None
    assert memory.available_bytes(tree.root) == 612 * MB


def test_v1_parent_with_the_tighter_limit(tree):
    tree.cgroups("5:cpu,memory:/outer/inner")
    tree.v1("/outer/inner", NO_V1_LIMIT, 1 * GB, 0)
    tree.v1("/outer", 3 * GB, 2 * GB, 200 * MB)
    assert memory.cgroup_v1_available(tree.root) == 1 * GB + 200 * MB


def test_v2_limit_walks_up_the_parents(tree):
    tree.meminfo(20 * GB)
    tree.cgroups("0::/user.slice/app.slice/blender.scope")
    tree.v2("/user.slice/app.slice/blender.scope", "max", 1 * GB, 0)
    tree.v2("/user.slice/app.slice", 2 * GB, 1536 * MB, 100 * MB)  # the tightest: 612 MB
    tree.v2("/user.slice", 4 * GB, 1600 * MB, 100 * MB)
    # The root cgroup has no memory.max.
    assert memory.cgroup_v2_available(tree.root) == 612 * MB
    assert memory.cgroup_v1_available(tree.root) is None
    assert memory.available_bytes(tree.root) == 612 * MB


def test_a_level_missing_from_the_tree_leaves_its_parents(tree):
    """A container sees the host's path in /proc/self/cgroup but its own cgroup as the mount's root."""
    tree.cgroups("0::/system.slice/docker-1234.scope")
    tree.v2("", 1 * GB, 256 * MB, 0)
    assert memory.cgroup_v2_available(tree.root) == 768 * MB


def test_no_limit_is_no_source(tree):
    tree.meminfo(10 * GB)
    tree.cgroups("4:memory:/a", "0::/b")
    tree.v1("/a", NO_V1_LIMIT, 1 * GB, 0)
    tree.v1("", NO_V1_LIMIT, 1 * GB, 0)
    tree.v2("/b", "max", 1 * GB, 0)
    assert memory.cgroup_v1_available(tree.root) is None
    assert memory.cgroup_v2_available(tree.root) is None
    assert memory.available_bytes(tree.root) == 10 * GB


def test_meminfo_tighter_than_the_cgroup(tree):
    tree.meminfo(3 * GB)
    tree.cgroups("0::/box")
    tree.v2("/box", 16 * GB, 1 * GB, 0)
    assert memory.available_bytes(tree.root) == 3 * GB


def test_usage_past_the_limit_leaves_nothing(tree):
    tree.cgroups("0::/box")
    tree.v2("/box", 1 * GB, 1 * GB + 4096, 0)
    assert memory.available_bytes(tree.root) == 0


def test_nothing_readable_is_none(tree):
    assert memory.available_bytes(tree.root) is None
    assert memory.available_bytes(os.path.join(tree.root, "missing")) is None


def test_unreadable_or_garbled_files_are_skipped(tree):
    os.makedirs(os.path.join(tree.root, "proc", "meminfo"))  # a directory where the file should be
    tree.cgroups("0::/box", "4:memory:/box")
    tree.write("sys/fs/cgroup/box/memory.max", "a lot\n")
    tree.v1("/box", 2 * GB, 1 * GB, 0)
    os.remove(os.path.join(tree.root, "sys/fs/cgroup/memory/box/memory.stat"))
    tree.v1("", "garbage", 1 * GB, 0)
    assert memory.available_bytes(tree.root) is None


def test_a_cgroup_named_in_any_script(tree):
    tree.meminfo(4 * GB)
    tree.cgroups("0::/user.slice/caf\u00e9.scope")
    tree.v2("/user.slice/caf\u00e9.scope", 1 * GB, 512 * MB, 0)
    assert memory.available_bytes(tree.root) == 512 * MB


def test_this_machine_answers():
    """Whatever runs the tests has a /proc/meminfo (Linux) or another source: a positive number."""
    available = memory.available_bytes()
    assert available is None or available > 0


# ---------------------------------------------------------------------------------------------------------------
# estimate_bytes

ICOSPHERE = (10242, 30720, 20480)  # Blender's icosphere of 20,480 triangles (subdivisions 6)
GRID = (10201, 30200, 20000)  # a 100 x 100 grid, triangulated: 20,200 edges + 20,000 triangles - 10,000 faces


def estimate(cage, levels, **arguments):
    """memory.estimate_bytes with the core's plan estimate, as the add-on calls it."""
    vertices, edges, triangles = cage
    plan = _loopsub.estimate_plan_bytes(vertices, triangles, levels, arguments.get("vertex_channels", 3), edges)
    return memory.estimate_bytes(vertices, edges, triangles, levels, plan, **arguments)


def edges_of(triangles):
    pairs = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    return len(np.unique(pairs, axis=0))


@pytest.mark.parametrize("levels", range(0, 6))
def test_output_counts_and_the_plan_estimate_are_the_cores(levels):
    positions, triangles = icosahedron()
    counts = (len(positions), edges_of(triangles), len(triangles))
    plan = _loopsub.Plan(triangles, len(positions), levels)
    deeper = _loopsub.Plan(triangles, len(positions), levels + 1)  # lists the edges of level `levels`
    assert memory.output_counts(*counts, levels) == (plan.num_output_vertices, len(deeper.level_edges(levels)),
                                                     plan.num_output_triangles)
    # The core refuses past its limit and says how much it would need: its own estimate, for 3 channels.
    with pytest.raises(MemoryError) as refused:
        _loopsub.Plan(triangles, len(positions), levels, memory_limit_bytes=1)
    vertices, edges, triangles = counts
    assert _loopsub.estimate_plan_bytes(vertices, triangles, levels, num_edges=edges) == refused.value.required_bytes


@pytest.mark.parametrize("limit_surface", [True, False])
@pytest.mark.parametrize("version", [(3, 4, 1), (4, 5, 15)])
@pytest.mark.parametrize("drawn", [True, False])
def test_the_estimate_grows_fourfold_per_level(limit_surface, version, drawn):
    """Each level has four times the triangles: the estimate tends to four times the last as the fixed costs fade."""
    estimates = [estimate(ICOSPHERE, levels, uv_layers=1, limit_surface=limit_surface, version=version,
                          drawn=drawn) for levels in range(0, 8)]
    ratios = [later / earlier for earlier, later in zip(estimates, estimates[1:])]
    assert all(ratio > 1 for ratio in ratios)
    assert all(3.85 < ratio <= 4 for ratio in ratios[4:])


def test_what_adds_to_the_estimate():
    def changed(**changes):
        arguments = dict(uv_layers=1, limit_surface=True, version=(4, 5, 15), drawn=True)
        arguments.update(changes)
        return estimate(ICOSPHERE, 4, **arguments)

    base = changed()
    assert changed(uv_layers=2) > base > changed(uv_layers=0)
    assert changed(corner_channels=4) > base and changed(vertex_channels=5) > base
    # Vertex groups: their weights above zero, a few per vertex however many groups there are.
    assert changed(groups=200, group_weights=4.0) > changed(groups=200, group_weights=1.0) > base
    assert changed(groups=2, group_weights=4.0) == changed(groups=2, group_weights=2.0)  # no more than one per group
    assert changed(limit_surface=False) < base
    assert changed(version=(3, 4, 1), limit_surface=False) > changed(limit_surface=False)  # 3.4 copies the result
    assert changed(drawn=False, limit_surface=False) < changed(limit_surface=False)


# Peak growth of RSS (MiB) when an entry is added to a UV-mapped, smooth-shaded cage in Blender (background mode, or
# Blender 3.4.1's interface under Xvfb and Mesa for `drawn`), through the settling of its limit normals, an evaluation
# of the depsgraph and an edit: the calibration of memory.py. (version, cage, levels, limit surface, UV maps, drawn,
# MiB).
MEASURED = [
    ((3, 4, 1), ICOSPHERE, 1, True, 1, False, 75), ((3, 4, 1), ICOSPHERE, 2, True, 1, False, 302),
    ((3, 4, 1), ICOSPHERE, 3, True, 1, False, 1044), ((3, 4, 1), ICOSPHERE, 4, True, 1, False, 3905),
    ((3, 4, 1), ICOSPHERE, 5, True, 1, False, 15384), ((3, 4, 1), ICOSPHERE, 3, False, 1, False, 544),
    ((3, 4, 1), ICOSPHERE, 5, False, 1, False, 8230), ((3, 4, 1), GRID, 5, True, 1, False, 15015),
    ((3, 4, 1), GRID, 5, False, 1, False, 8015), ((3, 4, 1), ICOSPHERE, 3, True, 2, False, 1237),
    ((3, 4, 1), ICOSPHERE, 3, False, 0, False, 362),
    ((3, 4, 1), ICOSPHERE, 2, True, 1, True, 404), ((3, 4, 1), ICOSPHERE, 3, True, 1, True, 1245),
    ((3, 4, 1), ICOSPHERE, 4, True, 1, True, 4333), ((3, 4, 1), GRID, 4, True, 1, True, 4211),
    ((3, 4, 1), ICOSPHERE, 5, False, 1, True, 11791), ((3, 4, 1), GRID, 4, False, 1, True, 2791),
    ((4, 5, 15), ICOSPHERE, 1, True, 1, False, 71), ((4, 5, 15), ICOSPHERE, 2, True, 1, False, 285),
    ((4, 5, 15), ICOSPHERE, 3, True, 1, False, 1035), ((4, 5, 15), ICOSPHERE, 5, True, 1, False, 15075),
    ((4, 5, 15), ICOSPHERE, 5, False, 1, False, 4822), ((4, 5, 15), GRID, 5, True, 1, False, 14678),
    ((4, 5, 15), GRID, 4, False, 1, False, 1216), ((4, 5, 15), ICOSPHERE, 3, False, 2, False, 416),
    ((4, 5, 15), ICOSPHERE, 3, False, 0, False, 223), ((4, 5, 15), ICOSPHERE, 3, True, 2, False, 1127),
]


@pytest.mark.parametrize("version, cage, levels, limit_surface, uv_layers, drawn, measured", MEASURED)
def test_the_estimate_covers_the_measured_peaks(version, cage, levels, limit_surface, uv_layers, drawn, measured):
    estimated = estimate(cage, levels, uv_layers=uv_layers, limit_surface=limit_surface, version=version,
                         drawn=drawn) / MB
    assert estimated >= measured
    if levels >= 3:
        assert estimated <= 1.5 * measured


# ---------------------------------------------------------------------------------------------------------------
# fits, describe


def test_fits_keeps_a_reserve():
    available = 10 * GB
    reserve = memory.reserve_bytes(available)
    assert reserve == GB + 256 * MB
    assert memory.fits(available - reserve, available)
    assert not memory.fits(available - reserve + 1, available)
    assert not memory.fits(available + 1, available, reserve=0)
    assert memory.fits(available, available, reserve=0)
    assert memory.fits(10**15, None)  # nothing known: no check


def test_describe_in_gb_and_mb():
    assert memory.describe(31 * GB + 123, int(9.23 * GB), "Level 4") == "Level 4 needs about 31 GB; 9.2 GB are free"
    assert memory.describe(int(2.26 * GB), 900 * MB, "Level 3") == "Level 3 needs about 2.3 GB; 900 MB are free"
    assert memory.describe(313 * MB + 5, 95 * MB, "Level 2") == "Level 2 needs about 313 MB; 95 MB are free"
    assert memory.describe(int(9.97 * GB), 3 * GB, "Level 5") == "Level 5 needs about 10 GB; 3 GB are free"
    assert memory.describe(1000 * MB, 0, "Level 1") == "Level 1 needs about 1 GB; 0 MB are free"


def test_describe_never_reads_the_same_amount_twice():
    """A need just past what is free, rounded alike, gets the decimals that part them (it read "Level 5 needs about
    21 GB; 21 GB are free")."""
    assert (memory.describe(int(21.3 * GB), int(21.1 * GB), "Level 5")
            == "Level 5 needs about 21.3 GB; 21.1 GB are free")
    assert (memory.describe(int(2.26 * GB), int(2.255 * GB), "Level 3")
            == "Level 3 needs about 2.26 GB; 2.25 GB are free")
    assert (memory.describe(int(500.4 * MB), int(500.2 * MB), "Level 2")
            == "Level 2 needs about 500.4 MB; 500.2 MB are free")


def test_describe_says_when_the_reserve_refuses():
    assert (memory.describe(int(8.5 * GB), int(9.2 * GB), "Level 4")
            == "Level 4 needs about 8.5 GB; 9.2 GB are free, less 1.2 GB kept for Blender and the system")
