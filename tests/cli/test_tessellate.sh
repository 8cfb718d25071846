# --tessellate N on OpenSubdiv's shapes: valid OBJ output with the counts a rate of N gives (V + E (N - 1) +
# F (N - 1)(N - 2) / 2 points, F N^2 triangles), a normal and a UV for every corner, and at N = 2^L the points (and
# each corner's UV) of --levels L --limit.
source "$(dirname "$0")/cli_lib.sh"
require_shapes

for shape in loop_cube loop_cube_creases0 loop_fvar_bound0 loop_icos_semisharp loop_pole8 loop_xord_interior; do
  in="$SHAPES/$shape.obj"
  v=$(count_lines v "$in")
  f=$(count_lines f "$in")
  e=$(count_edges "$in")
  for rules in hoppe94 opensubdiv; do
    for rate in 1 3 5; do
      out="$WORK/$shape.$rules.$rate.obj"
      run_cli 0 "$in" "$out" --tessellate "$rate" --rules "$rules"
      check_valid_obj "$out" $((v + e * (rate - 1) + f * (rate - 1) * (rate - 2) / 2)) $((f * rate * rate))
      grep -q '^f [0-9]*/[0-9]*/[0-9]* \|^f [0-9]*//[0-9]* ' "$out" || fail "$out: faces without normals"
      if grep -q '^vt ' "$in"; then
        grep -q '^f [0-9]*/[0-9][0-9]*/' "$out" || fail "$out: the input has UVs but the faces have no vt index"
      fi
      grep -q '^t ' "$out" && fail "$out: a tessellation has no tags to feed back, yet wrote $(grep -c '^t ' "$out")"
    done
  done
  # Rate 4 is level 2 on the limit surface: the same points (sorted, as the numbering differs inside the faces), and
  # where the input has UVs, the same UV at every corner (each corner's point with its vt, refined as levels refine).
  run_cli 0 "$in" "$WORK/t4.obj" --tessellate 4 --rules opensubdiv
  run_cli 0 "$in" "$WORK/l2.obj" --levels 2 --limit --rules opensubdiv
  # (A regular triangle's points come from its box spline, not the limit masks: the same within rounding, 1e-5.)
  python3 - "$WORK/t4.obj" "$WORK/l2.obj" <<'PY' || fail "$shape: --tessellate 4 is not --levels 2 --limit"
import sys
def read(path):
    rows = {"v": [], "vt": []}
    corners = []
    for line in open(path):
        parts = line.split()
        if parts and parts[0] in rows:
            rows[parts[0]].append(tuple(float(x) for x in parts[1:]))
        elif parts and parts[0] == "f":
            for corner in parts[1:]:
                index = corner.split("/")
                if len(index) > 1 and index[1]:
                    corners.append(rows["v"][int(index[0]) - 1][:3] + rows["vt"][int(index[1]) - 1][:2])
    return sorted(rows["v"]), corners
def match(a, b, size):
    unmatched = sorted(b)
    for p in sorted(a):
        near = min(range(len(unmatched)), key=lambda i: max(abs(p[k] - unmatched[i][k]) for k in range(size)),
                   default=None)
        if near is None or max(abs(p[k] - unmatched[near][k]) for k in range(size)) > 1e-5:
            sys.exit(f"no point of the refinement near {p}")
        unmatched.pop(near)
    return not unmatched
(points_a, corners_a), (points_b, corners_b) = read(sys.argv[1]), read(sys.argv[2])
sys.exit(0 if match(points_a, points_b, 3) and match(sorted(set(corners_a)), sorted(set(corners_b)), 5) else 1)
PY
done

# --boundary none: the faces at a boundary edge not tagged sharp have no limit surface and are left out, with the
# points inside their edges and themselves (the input's vertices stay, those of no face with a surface where they
# are); at rate 4 the points the faces use are those --levels 2 --limit --boundary none's faces use.
awk 'BEGIN {
  n = 6
  for (j = 0; j <= n; j++) for (i = 0; i <= n; i++) printf "v %d %g %d\n", i, 0.1 * ((i * 7 + j * 3) % 5), j
  for (j = 0; j < n; j++) for (i = 0; i < n; i++) {
    a = j * (n + 1) + i + 1; c = a + n + 1
    printf "f %d %d %d\nf %d %d %d\n", a, c + 1, c, a, a + 1, c + 1
  }
}' >"$WORK/open.obj"
for in in "$WORK/open.obj" "$SHAPES/loop_pole8.obj"; do
  for rate in 3 5; do
    run_cli 0 "$in" "$WORK/none.obj" --tessellate "$rate" --boundary none --rules opensubdiv
    counts=$(python3 - "$in" "$rate" <<'PY'
import sys
from collections import Counter
faces = [[int(c.split("/")[0]) for c in line.split()[1:]] for line in open(sys.argv[1]) if line.startswith("f ")]
vertices = sum(1 for line in open(sys.argv[1]) if line.startswith("v "))
edges = Counter(tuple(sorted((f[k], f[(k + 1) % 3]))) for f in faces for k in range(3))
boundary = {v for e, n in edges.items() if n == 1 for v in e}
kept = [f for f in faces if not boundary & set(f)]
kept_edges = {tuple(sorted((f[k], f[(k + 1) % 3]))) for f in kept for k in range(3)}
r = int(sys.argv[2])
print(vertices + len(kept_edges) * (r - 1) + len(kept) * (r - 1) * (r - 2) // 2, len(kept) * r * r)
PY
)
    check_valid_obj "$WORK/none.obj" $counts
  done
  run_cli 0 "$in" "$WORK/none4.obj" --tessellate 4 --boundary none --rules opensubdiv
  run_cli 0 "$in" "$WORK/none_l2.obj" --levels 2 --limit --boundary none --rules opensubdiv
  python3 - "$WORK/none4.obj" "$WORK/none_l2.obj" <<'PY' || fail "$in: --tessellate 4 --boundary none is not --levels 2"
import sys
def used_points(path):
    v, used = [], set()
    for line in open(path):
        if line.startswith("v "):
            v.append(tuple(float(x) for x in line.split()[1:4]))
        elif line.startswith("f "):
            used.update(int(c.split("/")[0]) - 1 for c in line.split()[1:])
    return [v[i] for i in used]
a, b = used_points(sys.argv[1]), used_points(sys.argv[2])
near = all(any(max(abs(x - y) for x, y in zip(p, q)) <= 1e-5 for q in b) for p in a)
sys.exit(0 if len(a) == len(b) > 0 and near else 1)
PY
done

run_cli 2 "$SHAPES/loop_cube.obj" "$WORK/x.obj" --tessellate 0
expect_stderr "--tessellate must be >= 1, got 0"
run_cli 2 "$SHAPES/loop_cube.obj" "$WORK/x.obj" --tessellate 4097
expect_stderr "--tessellate must be <= 4096"
run_cli 2 "$SHAPES/loop_cube.obj" "$WORK/x.obj" --tessellate 2 --levels 1
expect_stderr "--levels, --tessellate and --camera exclude each other"
run_cli 2 "$SHAPES/loop_cube.obj" "$WORK/x.obj"
expect_stderr "--levels N, --tessellate N or --camera is required"
# --camera: rates from the screen. A ground plane seen from a low camera: the near edges get more segments than the
# far ones, the rates stay within --max-rate, and the result is as valid as any other.
cat >"$WORK/ground.obj" <<'OBJ'
v -4 0 -4
v 4 0 -4
v 4 0 4
v -4 0 4
v 0 0 -4
v 0 0 4
f 1 6 5
f 1 4 6
f 5 3 2
f 5 6 3
OBJ
run_cli 0 "$WORK/ground.obj" "$WORK/near.obj" --camera 0,1,6,0,0,0 --dicing-rate 8 --max-rate 32 --stats
grep -q '^f ' "$WORK/near.obj" || fail "--camera wrote no faces"
rate=$(sed -n 's/.* rate=\([0-9]*\) .*/\1/p' "$WORK/stdout")
[ "${rate:-0}" -gt 1 ] && [ "$rate" -le 32 ] || fail "--camera: the largest rate $rate is not in 2..32: $(cat "$WORK/stdout")"
run_cli 0 "$WORK/ground.obj" "$WORK/far.obj" --camera 0,1,60,0,0,0 --dicing-rate 8 --max-rate 32
[ "$(count_lines f "$WORK/far.obj")" -lt "$(count_lines f "$WORK/near.obj")" ] ||
  fail "--camera: a camera ten times farther away gave no fewer triangles"
# By deviation the cut follows the shape: a ground of 8 x 8 quads with bumps (every other inner vertex raised by 1)
# takes over three times the triangles it takes flat, where only the rounding of its corners is cut.
ground_of_quads() {  # $1: 1 for bumps
  awk -v bumps="$1" 'BEGIN {
    n = 8
    for (j = 0; j <= n; j++)
      for (i = 0; i <= n; i++)
        printf "v %d %d %d\n", i - n / 2, (bumps && i % 2 == 0 && j % 2 == 0 && i > 0 && i < n && j > 0 && j < n), j - n / 2
    for (j = 0; j < n; j++)
      for (i = 0; i < n; i++) {
        a = j * (n + 1) + i + 1; c = a + n + 1
        printf "f %d %d %d\nf %d %d %d\n", a, c, c + 1, a, c + 1, a + 1
      }
  }'
}
ground_of_quads 0 >"$WORK/flat.obj"
ground_of_quads 1 >"$WORK/bumps.obj"
run_cli 0 "$WORK/flat.obj" "$WORK/flat_cut.obj" --camera 0,3,8,0,0,0 --dicing-rate 0.2 --dicing-measure deviation
run_cli 0 "$WORK/bumps.obj" "$WORK/bumps_cut.obj" --camera 0,3,8,0,0,0 --dicing-rate 0.2 --dicing-measure deviation
flat=$(count_lines f "$WORK/flat_cut.obj")
bumps=$(count_lines f "$WORK/bumps_cut.obj")
[ "$flat" -gt 0 ] && [ $((3 * flat)) -lt "$bumps" ] ||
  fail "--dicing-measure deviation: bumps took $bumps triangles, flat ground $flat (expected over 3 times)"
run_cli 2 "$WORK/ground.obj" "$WORK/x.obj" --camera 0,1,6,0,0,0 --dicing-measure area
expect_stderr "--dicing-measure expects length or deviation, got 'area'"
run_cli 2 "$WORK/ground.obj" "$WORK/x.obj" --dicing-rate 2
expect_stderr "--dicing-rate needs --camera"
run_cli 2 "$WORK/ground.obj" "$WORK/x.obj" --camera 0,1,6
expect_stderr "--camera expects 6 numbers separated by commas"
run_cli 2 "$WORK/ground.obj" "$WORK/x.obj" --camera 0,1,6,0,0,0 --tessellate 2
expect_stderr "--levels, --tessellate and --camera exclude each other"
run_cli 2 "$WORK/ground.obj" "$WORK/x.obj" --camera 0,0,0,0,0,0
expect_stderr "the eye, the target and --up must span a view"
finish
