"""compare_obj.py A.obj B.obj TOLERANCE: the same faces and tags (every line but v lines identical) and the same
vertices within TOLERANCE times A's bounding-box diagonal. Exit 0 when equal, 1 with the first difference."""
import sys

import numpy as np


def read(path):
    positions, rest = [], []
    with open(path) as file:
        for line in file:
            if line.startswith("v "):
                positions.append([float(x) for x in line.split()[1:4]])
            else:
                rest.append(line.rstrip("\r\n"))
    return np.array(positions, dtype=np.float64).reshape(-1, 3), rest


a_positions, a_rest = read(sys.argv[1])
b_positions, b_rest = read(sys.argv[2])
tolerance = float(sys.argv[3])
if a_rest != b_rest:
    line = next(i for i, (x, y) in enumerate(zip(a_rest + [""], b_rest + [""])) if x != y)
    sys.exit(f"faces, texture coordinates or tags differ (non-v line {line})")
if a_positions.shape != b_positions.shape:
    sys.exit(f"{len(a_positions)} vertices against {len(b_positions)}")
diagonal = np.linalg.norm(a_positions.max(axis=0) - a_positions.min(axis=0)) if len(a_positions) else 0.0
worst = np.abs(a_positions - b_positions).max() if len(a_positions) else 0.0
if worst > tolerance * diagonal:
    sys.exit(f"positions differ by {worst:.3g}, more than {tolerance} of the diagonal {diagonal:.3g}")
