"""read_obj: the command line's OBJ reader (native/obj/) in Python, the one reader of OpenSubdiv's tags the demo
uses: the mesh with polygons split, the tags 0-based, the rules the tags set; what it cannot read raised at its
line (a tag's vertex out of range is the core's to find, as for the command line)."""
import numpy as np
import pytest

import _loopsub

TAGGED = """v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0.5 0.5 1
f 1 2 3 4
f 1 2 5
f 2 3 5
f 3 4 5
f 4 1 5
t crease 2/1/0 0 1 2.5
t crease 2/1/0 1 2 10
t corner 1/1/0 3 4
t interpolateboundary 1/0/0 1
t creasemethod 0/0/1 chaikin
"""


def test_the_mesh_and_its_tags(tmp_path):
    path = tmp_path / "tagged.obj"
    path.write_text(TAGGED)
    obj = _loopsub.read_obj(str(path))
    assert obj["positions"].dtype == np.float32 and obj["positions"].shape == (5, 3)
    assert obj["triangles"].dtype == np.int32 and obj["triangles"].shape == (6, 3)  # the quad split in two
    assert obj["crease_edges"].tolist() == [[0, 1], [1, 2]]
    assert obj["crease_sharpness"].tolist() == [2.5, 10.0]
    assert obj["corner_vertices"].tolist() == [3] and obj["corner_sharpness"].tolist() == [4.0]
    assert obj["cone_vertices"].shape == (0,) and obj["hole_triangles"].shape == (0,)
    assert (obj["boundary"], obj["crease_method"], obj["uv_interpolation"]) == \
        ("edges-and-corners", "chaikin", None)
    # What it reads, a plan takes as is.
    plan = _loopsub.Plan(obj["triangles"], len(obj["positions"]), 1, rules="opensubdiv",
                         crease_edges=obj["crease_edges"], crease_sharpness=obj["crease_sharpness"],
                         corner_vertices=obj["corner_vertices"], corner_sharpness=obj["corner_sharpness"],
                         boundary=obj["boundary"], crease_method=obj["crease_method"])
    assert plan.num_output_triangles == 24


def test_what_it_cannot_read_is_raised_at_its_line(tmp_path):
    path = tmp_path / "bad.obj"
    path.write_text(TAGGED + "t corner 1/1/0 3\n")
    with pytest.raises(_loopsub.InputError, match=r"bad\.obj:16: "):
        _loopsub.read_obj(str(path))
    with pytest.raises(_loopsub.InputError):
        _loopsub.read_obj(str(tmp_path / "missing.obj"))
