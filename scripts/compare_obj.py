"""compare_obj.py A.obj B.obj TOLERANCE: the same faces and tags (every line but v, vt and vn lines identical), the
same vertices within TOLERANCE times A's bounding-box diagonal, the same texture coordinates and normals within
TOLERANCE (smooth UVs and normals are sums of floats: another instruction set may round their last bit
differently). Exit 0 when equal, 1 with the first difference."""
import sys

import numpy as np

NUMBERED = {"v": 3, "vt": 2, "vn": 3}


def read(path):
    numbers, rest = {key: [] for key in NUMBERED}, []
    with open(path) as file:
        for line in file:
            key = line.split(" ", 1)[0]
            if key in NUMBERED:
                numbers[key].append([float(x) for x in line.split()[1:1 + NUMBERED[key]]])
            else:
                rest.append(line.rstrip("\r\n"))
    return {key: np.array(values, dtype=np.float64).reshape(-1, NUMBERED[key]) for key, values in numbers.items()}, rest


a_numbers, a_rest = read(sys.argv[1])
b_numbers, b_rest = read(sys.argv[2])
tolerance = float(sys.argv[3])
if a_rest != b_rest:
    line = next(i for i, (x, y) in enumerate(zip(a_rest + [""], b_rest + [""])) if x != y)
    sys.exit(f"faces or tags differ (line {line} of those that are not v, vt or vn)")
for key in NUMBERED:
    a, b = a_numbers[key], b_numbers[key]
    if a.shape != b.shape:
        sys.exit(f"{len(a)} '{key}' lines against {len(b)}")
    if not len(a):
        continue
    scale = np.linalg.norm(a.max(axis=0) - a.min(axis=0)) if key == "v" else 1.0
    worst = np.abs(a - b).max()
    if worst > tolerance * scale:
        sys.exit(f"'{key}' values differ by {worst:.3g}, more than {tolerance} of {scale:.3g}")
