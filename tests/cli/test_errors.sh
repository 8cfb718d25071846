# Bad command lines exit 2 with the usage, bad inputs exit 1 with "loopsub: error: " and a message that says
# what and where; nothing crashes. A quad mesh is triangulated, with a notice.
source "$(dirname "$0")/cli_lib.sh"
require_shapes

good="$SHAPES/loop_tetrahedron.obj"
out="$WORK/out.obj"

# Usage errors: exit 2, the message and the usage on stderr.
run_cli 2 "$good" "$out" --levels 1 --frobnicate
expect_stderr "loopsub: error: unknown option '--frobnicate'"
expect_stderr "usage: loopsub IN.obj OUT.obj --levels N"
run_cli 2 "$good" "$out" --levels -1
expect_stderr "loopsub: error: --levels must be >= 0, got -1"
run_cli 2 "$good" "$out" --levels 65
expect_stderr "loopsub: error: --levels must be <= 64, got 65"
run_cli 2 "$good" "$out" --levels two
expect_stderr "loopsub: error: --levels expects an integer, got 'two'"
run_cli 2 "$good" "$out" --levels 1.5
expect_stderr "--levels expects an integer, got '1.5'"
run_cli 2 "$good" "$out" --levels 1 --crease-threshold 0.5x
expect_stderr "--crease-threshold expects a number, got '0.5x'"
run_cli 2 "$good" "$out" --levels 1 --crease-threshold -1
expect_stderr "--crease-threshold must be >= 0"
run_cli 2 "$good" "$out" --levels 1 --threads 0
expect_stderr "--threads must be >= 1"
run_cli 2 "$good" "$out" --levels 1 --threads 257
expect_stderr "--threads must be <= 256, got 257"
run_cli 2 "$good" "$out" --levels 1 --rules catmull
expect_stderr "--rules expects hoppe94 or opensubdiv, got 'catmull'"
run_cli 2 "$good" "$out" --levels 1 --boundary sideways
expect_stderr "--boundary expects edges, edges-and-corners or none"
run_cli 2 "$good" "$out" --levels 1 --crease-method wobbly
expect_stderr "--crease-method expects uniform or chaikin"
run_cli 2 "$good" "$out" --levels
expect_stderr "--levels needs a value"
run_cli 2 "$good" "$out"
expect_stderr "--levels N, --tessellate N or --camera is required"
run_cli 2 "$good" --levels 1
expect_stderr "expected IN.obj and OUT.obj"
run_cli 2 "$good" "$out" --levels=1 --scalar=yes
expect_stderr "--scalar takes no value"

run_cli 0 --help
grep -q -- "--memory-limit-mb N" "$WORK/stdout" || fail "--help does not list the options: $(cat "$WORK/stdout")"

# Input errors: exit 1.
run_cli 1 "$WORK/missing.obj" "$out" --levels 1
expect_stderr "loopsub: error: $WORK/missing.obj: cannot open for reading"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 9\n' >"$WORK/bad_index.obj"
run_cli 1 "$WORK/bad_index.obj" "$out" --levels 1
expect_stderr "loopsub: error: $WORK/bad_index.obj:5: vertex index 9 is out of range"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n' >"$WORK/bad_negative.obj"
run_cli 1 "$WORK/bad_negative.obj" "$out" --levels 1
expect_stderr "bad_negative.obj:4: vertex index -4 is out of range"

printf 'v 0 0 0\nv 1 zero 0\n' >"$WORK/garbage.obj"
run_cli 1 "$WORK/garbage.obj" "$out" --levels 1
expect_stderr "garbage.obj:2: expected a number for coordinate, got 'zero'"

printf 'v 0 0 0\nv 1 nan 0\n' >"$WORK/nan.obj"
run_cli 1 "$WORK/nan.obj" "$out" --levels 1
expect_stderr "nan.obj:2: coordinate is not finite"

# What Blender stores for an infinite coordinate: finite, but its refinement would overflow to NaN.
sed 's/^v  1  1  1$/v 1 1 3.4028235e38/' "$good" >"$WORK/huge.obj"
grep -q "3.4028235e38" "$WORK/huge.obj" || fail "the tetrahedron has no vertex '1 1 1' to make huge"
run_cli 1 "$WORK/huge.obj" "$out" --levels 2 --rules hoppe94
expect_stderr "has a value too large to refine"

run_cli 1 "$SHAPES/loop_nonman_edges.obj" "$out" --levels 1
expect_stderr "loop_nonman_edges.obj:193: the face repeats vertex 46"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 1 -2\n' >"$WORK/negative_sharpness.obj"
run_cli 1 "$WORK/negative_sharpness.obj" "$out" --levels 1
expect_stderr "sharpness"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nt crease 2/1/0 0 3 1\n' >"$WORK/not_an_edge.obj"
run_cli 1 "$WORK/not_an_edge.obj" "$out" --levels 1
expect_stderr "not_an_edge.obj:6: crease 0-3 is not an edge of the mesh"

# What the core refuses, said at the line of the file: the face as the file has it (a polygon, its vertex numbered from
# 1), the tag of a crease, corner or cone (its vertex numbered from 0), whatever way the mesh is cut.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\n\nf 2 4 2 3\n' >"$WORK/degenerate_polygon.obj"
for way in "--levels 1" "--tessellate 2" "--camera 0,0,5,0,0,0"; do
  run_cli 1 "$WORK/degenerate_polygon.obj" "$out" $way
  expect_stderr "loopsub: error: $WORK/degenerate_polygon.obj:7: the face repeats vertex 2 and cannot be split into triangles that do not"
done
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 1 1\n\nt crease 4/1/0 1 2 2 9 1\n' >"$WORK/crease_vertex.obj"
run_cli 1 "$WORK/crease_vertex.obj" "$out" --levels 1
expect_stderr "loopsub: error: $WORK/crease_vertex.obj:7: crease vertex 9 is out of range (3 vertices, tags count from 0)"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt cone 1/0/0 0\nt corner 2/1/0 1 2 nan\n' >"$WORK/corner_nan.obj"
run_cli 1 "$WORK/corner_nan.obj" "$out" --levels 1
expect_stderr "loopsub: error: $WORK/corner_nan.obj:6: tag 'corner' gives sharpness nan; a sharpness is a finite number >= 0"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt cone 1/0/0 3\n' >"$WORK/cone_vertex.obj"
run_cli 1 "$WORK/cone_vertex.obj" "$out" --levels 1 --rules hoppe94
expect_stderr "loopsub: error: $WORK/cone_vertex.obj:5: cone vertex 3 is out of range (3 vertices, tags count from 0)"
run_cli 2 "$good" "$out" --camera 0,0,5,0,0,0 --dicing-measure area
expect_stderr "loopsub: error: --dicing-measure expects length or deviation, got 'area'"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt interpolateboundary 1/0/0 7\n' >"$WORK/boundary_seven.obj"
run_cli 1 "$WORK/boundary_seven.obj" "$out" --levels 1
expect_stderr "boundary_seven.obj:5: interpolateboundary 7 is unknown"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt hole 1/0/0 1\n' >"$WORK/hole_past_the_faces.obj"
run_cli 1 "$WORK/hole_past_the_faces.obj" "$out" --levels 1
expect_stderr "hole_past_the_faces.obj:5: hole face 1 is out of range (1 faces"

run_cli 2 "$good" "$out" --levels 1 --uv-interpolation linear
expect_stderr "--uv-interpolation expects none, corners, corners-plus1, corners-plus2, boundaries or all, got 'linear'"

# 4 x 4^8 triangles of three 4-byte indices alone are 3 MiB: the message gives the need against the limit.
run_cli 1 "$good" "$out" --levels 8 --memory-limit-mb 1
expect_stderr "loopsub: error: "
expect_stderr "bytes"
grep -Eq 'MiB needed, --memory-limit-mb is 1\)$' "$WORK/stderr" || fail "no MiB needed vs limit: $(cat "$WORK/stderr")"
needed=$(sed -E 's/.*\(([0-9]+) MiB needed.*/\1/' "$WORK/stderr")
((needed >= 3)) || fail "the refinement reportedly needs only $needed MiB: $(cat "$WORK/stderr")"

run_cli 1 "$good" "$WORK/no/such/directory/out.obj" --levels 1
expect_stderr "cannot open for writing"

# An empty file is an empty mesh.
: >"$WORK/empty.obj"
run_cli 0 "$WORK/empty.obj" "$out" --levels 2
[ -s "$out" ] && fail "the output of an empty mesh is not empty: $(head -3 "$out")"

# A cube of six quads: triangulated (two triangles each), with a notice, then subdivided.
cat >"$WORK/quads.obj" <<'OBJ'
v -1 -1 -1
v 1 -1 -1
v 1 1 -1
v -1 1 -1
v -1 -1 1
v 1 -1 1
v 1 1 1
v -1 1 1
f 1 4 3 2
f 5 6 7 8
f 1 2 6 5
f 2 3 7 6
f 3 4 8 7
f 4 1 5 8
OBJ
run_cli 0 "$WORK/quads.obj" "$out" --levels 1
expect_stderr "loopsub: note: $WORK/quads.obj: triangulated 6 polygon(s) with more than 3 corners"
check_valid_obj "$out" 26 48  # 8 vertices + 18 edges (12 sides, 6 diagonals); 12 triangles x 4
# Nothing else to say of a closed, consistently wound cube.
grep -q "run the same way" "$WORK/stderr" && fail "a consistently wound cube noted as flipped: $(cat "$WORK/stderr")"

# An octahedron with one face wound against its neighbours: its three edges are infinitely sharp, and the CLI says so.
cat >"$WORK/flipped.obj" <<'OBJ'
v 1 0 0
v 0 1 0
v -1 0 0
v 0 -1 0
v 0 0 1
v 0 0 -1
f 5 2 1
f 2 1 6
f 2 3 5
f 3 2 6
f 3 4 5
f 4 3 6
f 4 1 5
f 1 4 6
OBJ
for way in "--levels 1" "--tessellate 2"; do
  run_cli 0 "$WORK/flipped.obj" "$out" $way
  expect_stderr "loopsub: note: $WORK/flipped.obj: 3 edge(s) along which two faces run the same way (a face wound against its neighbours), infinitely sharp"
done

# A negative sharpness and a directory for a file: named where they are.
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 1 -1\n' >"$WORK/negative.obj"
run_cli 1 "$WORK/negative.obj" "$out" --levels 1
expect_stderr "loopsub: error: $WORK/negative.obj:5: tag 'crease' gives sharpness -1.000000; a sharpness is a finite number >= 0"
run_cli 1 "$WORK" "$out" --levels 1
expect_stderr "loopsub: error: $WORK: is a directory, not an OBJ file"

finish
