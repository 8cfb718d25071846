# --stats prints exactly one line with the timings and counts; --scalar and --threads show in it and give the
# same surface as the defaults.
source "$(dirname "$0")/cli_lib.sh"
require_shapes

in="$SHAPES/loop_cube_creases0.obj"  # 8 vertices, 12 triangles, 18 edges
number='[0-9]+(\.[0-9]+)?'

run_cli 0 "$in" "$WORK/auto.obj" --levels 2 --stats
[ "$(wc -l <"$WORK/stdout")" -eq 1 ] || fail "--stats printed $(wc -l <"$WORK/stdout") lines: $(cat "$WORK/stdout")"
grep -Eqx "topology_ms=$number evaluate_ms=$number levels=2 vertices_in=8 triangles_in=12 vertices_out=98 triangles_out=192 kernel=(scalar|sse4\.1|avx2) threads=1" "$WORK/stdout" \
  || fail "unexpected --stats line: $(cat "$WORK/stdout")"
# The shape's normals are skipped with a note; nothing else goes to stderr.
grep -v "^loopsub: note: .*skipped 36 'vn' statements" "$WORK/stderr" | grep -q . && fail "unexpected stderr: $(cat "$WORK/stderr")"

run_cli 0 "$in" "$WORK/scalar.obj" --levels 2 --stats --scalar --threads 2
grep -Eqx "topology_ms=$number evaluate_ms=$number levels=2 vertices_in=8 triangles_in=12 vertices_out=98 triangles_out=192 kernel=scalar threads=2" "$WORK/stdout" \
  || fail "unexpected --stats line with --scalar --threads 2: $(cat "$WORK/stdout")"
# Same vertex order, so the point sets must match within float rounding of the SIMD paths.
check_same_points "$WORK/auto.obj" "$WORK/scalar.obj" 1e-6
cmp -s <(grep -v '^v ' "$WORK/auto.obj") <(grep -v '^v ' "$WORK/scalar.obj") \
  || fail "--scalar --threads 2 changed the faces, UVs or tags"

# Level 0: the input's counts come out unchanged.
run_cli 0 "$in" "$WORK/zero.obj" --levels 0 --stats
grep -Eq " levels=0 vertices_in=8 triangles_in=12 vertices_out=8 triangles_out=12 " "$WORK/stdout" \
  || fail "unexpected --stats line at level 0: $(cat "$WORK/stdout")"

# The OBJ on standard output: the line goes to stderr, and stdout is the OBJ alone.
run_cli 0 "$in" /dev/stdout --levels 1 --stats
grep -q "^topology_ms=" "$WORK/stderr" || fail "--stats with the OBJ on stdout: no line on stderr: $(cat "$WORK/stderr")"
grep -q "topology_ms=" "$WORK/stdout" && fail "--stats with the OBJ on stdout: the line is inside the OBJ"
grep -q "^f " "$WORK/stdout" || fail "--stats with the OBJ on stdout: no faces on stdout"

finish
