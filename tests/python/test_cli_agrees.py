"""The command-line tool (which derives its level tables: it evaluates once) gives, bit for bit, the positions the
module gives with stored tables, on a mesh with a boundary and a closed one."""
import os
import subprocess

import numpy as np
import pytest

import _loopsub
from conftest import grid, icosahedron

CLI = os.environ.get("LOOPSUB_CLI")


def write_obj(path, positions, triangles):
    with open(path, "w") as f:
        for p in positions.tolist():
            f.write("v %r %r %r\n" % tuple(float(np.float32(x)) for x in p))
        for t in (np.asarray(triangles) + 1).tolist():
            f.write("f %d %d %d\n" % tuple(t))


def read_positions(path):
    with open(path) as f:
        return np.array([[np.float32(x) for x in line.split()[1:4]] for line in f if line.startswith("v ")], np.float32)


@pytest.mark.skipif(CLI is None, reason="LOOPSUB_CLI (the built command-line tool) is set by ctest")
@pytest.mark.parametrize("mesh", ["grid", "icosahedron"])
@pytest.mark.parametrize("rules", ["hoppe94", "opensubdiv"])
def test_cli_positions_equal_the_modules_with_stored_tables(tmp_path, mesh, rules):
    positions, triangles = grid(9, seed=5, height=0.3) if mesh == "grid" else icosahedron()
    positions = np.asarray(positions, np.float32)
    write_obj(tmp_path / "in.obj", positions, triangles)
    subprocess.run([CLI, str(tmp_path / "in.obj"), str(tmp_path / "out.obj"), "--levels", "3", "--rules", rules],
                   check=True, capture_output=True)
    plan = _loopsub.Plan(triangles, len(positions), levels=3, rules=rules, level_tables="stored")
    expected = plan.evaluate(positions)
    got = read_positions(tmp_path / "out.obj")
    assert got.shape == expected.shape
    np.testing.assert_array_equal(got, expected)
