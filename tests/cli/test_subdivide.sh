# The CLI on OpenSubdiv's shapes: valid OBJ output with 4^L times the faces and V + E new vertices per level,
# the child crease / corner tags, cones kept, UV seams kept, and output that can be fed back in.
source "$(dirname "$0")/cli_lib.sh"
require_shapes

# Every shape but loop_nonman_edges (degenerate triangles, refused; see test_errors.sh), both rule sets, 1-2 levels.
for shape in loop_chaikin0 loop_cube loop_cube_creases0 loop_fvar_bound0 loop_icos_semisharp loop_icosahedron \
             loop_pole8 loop_saddle_edgecorner loop_tetrahedron loop_triangle_edgecorner loop_xord_interior; do
  in="$SHAPES/$shape.obj"
  v=$(count_lines v "$in")
  f=$(count_lines f "$in")
  e=$(count_edges "$in")
  for rules in hoppe94 opensubdiv; do
    for levels in 1 2; do
      out="$WORK/$shape.$rules.$levels.obj"
      run_cli 0 "$in" "$out" --levels "$levels" --rules "$rules"
      read -r v_out f_out < <(expected_counts "$v" "$e" "$f" "$levels")
      check_valid_obj "$out" "$v_out" "$f_out"
      if grep -q '^vt ' "$in"; then
        grep -q '^f [0-9]*/[0-9]* ' "$out" || fail "$out: the input has UVs but the faces have no vt index"
      fi
      [ -s "$WORK/stdout" ] && fail "loopsub wrote to stdout without --stats: $(cat "$WORK/stdout")"
    done
  done
done

# Semi-sharp creases under opensubdiv: sharpness 2.8 drops by one per level, and each crease edge has two children.
out="$WORK/cube_creases.obj"
run_cli 0 "$SHAPES/loop_cube_creases0.obj" "$out" --levels 1 --rules opensubdiv
[ "$(grep -c '^t crease 2/1/0 [0-9]* [0-9]* 1.8$' "$out")" -eq 4 ] || fail "$out: expected 4 crease tags of sharpness 1.8: $(grep '^t' "$out")"
grep -qx 't interpolateboundary 1/0/0 2' "$out" || fail "$out: the boundary tag of the input is not kept"
# Original vertices keep their indices: the tagged crease 1-3-2 is split at new vertices between them.
awk '$1 == "t" && $2 == "crease" { print ($4 < $5 ? $4 : $5) }' "$out" | sort -n | uniq | head -3 | tr '\n' ' ' | grep -qx '1 2 3 ' \
  || fail "$out: the child crease edges do not start at vertices 1, 2 and 3: $(grep '^t crease' "$out")"
# Hoppe94 carries the tag value over: the crease stays a crease at every level.
run_cli 0 "$SHAPES/loop_cube_creases0.obj" "$out" --levels 2 --rules hoppe94
[ "$(grep -c '^t crease 2/1/0 [0-9]* [0-9]* 2.8$' "$out")" -eq 8 ] || fail "$out: expected 8 crease tags of sharpness 2.8: $(grep '^t' "$out")"

# Corner sharpness decays too, on the same vertex indices (4: 2.5, 16: 4.5).
out="$WORK/icos_semisharp.obj"
run_cli 0 "$SHAPES/loop_icos_semisharp.obj" "$out" --levels 1 --rules opensubdiv
grep -qx 't corner 1/1/0 4 1.5' "$out" || fail "$out: no 't corner 1/1/0 4 1.5': $(grep '^t corner' "$out")"
grep -qx 't corner 1/1/0 16 3.5' "$out" || fail "$out: no 't corner 1/1/0 16 3.5': $(grep '^t corner' "$out")"
[ "$(grep -c '^t crease ' "$out")" -eq 30 ] || fail "$out: expected 30 child crease tags"

# Cones keep their vertex index.
cat >"$WORK/cone.obj" <<'OBJ'
v 0 0 1
v 1 0 0
v 0 1 0
v -1 0 0
v 0 -1 0
f 1 2 3
f 1 3 4
f 1 4 5
f 1 5 2
t cone 1/0/0 0
OBJ
run_cli 0 "$WORK/cone.obj" "$WORK/cone_out.obj" --levels 2
grep -qx 't cone 1/0/0 0' "$WORK/cone_out.obj" || fail "cone tag not written: $(grep '^t' "$WORK/cone_out.obj")"
check_valid_obj "$WORK/cone_out.obj" 41 64

# UVs: at level 0 every corner keeps its input UV; at level 1 a vertex on the cube's UV seam (vertex 1, with vt
# 1 and vt 9 in the input) still has two different UVs.
corner_uvs() {  # one line per face corner: its u and v
  awk '$1 == "vt" { n++; u[n] = $2; w[n] = $3 }
       $1 == "f"  { for (i = 2; i <= NF; i++) { split($i, c, "/"); printf "%.6f %.6f\n", u[c[2]], w[c[2]] } }' "$1"
}
run_cli 0 "$SHAPES/loop_cube_creases0.obj" "$WORK/uv0.obj" --levels 0
diff <(corner_uvs "$SHAPES/loop_cube_creases0.obj") <(corner_uvs "$WORK/uv0.obj") >/dev/null \
  || fail "--levels 0 changed the UVs of some corners"
run_cli 0 "$SHAPES/loop_cube_creases0.obj" "$WORK/uv1.obj" --levels 1
seam_uvs=$(awk '$1 == "vt" { n++; uv[n] = $2 " " $3 }
                $1 == "f"  { for (i = 2; i <= NF; i++) { split($i, c, "/"); if (c[1] == 1) seen[uv[c[2]]] = 1 } }
                END { for (k in seen) count++; print count + 0 }' "$WORK/uv1.obj")
[ "$seam_uvs" -ge 2 ] || fail "vertex 1 lies on a UV seam but has $seam_uvs distinct UV(s) at level 1"

# The file's interpolateboundary and creasemethod tags choose the rules unless a flag does; the output records them.
same_file() { cmp -s "$1" "$2"; }
saddle="$SHAPES/loop_saddle_edgecorner.obj"  # t interpolateboundary 1/0/0 1: edges and corners
run_cli 0 "$saddle" "$WORK/tag.obj" --levels 2 --rules opensubdiv
run_cli 0 "$saddle" "$WORK/corners.obj" --levels 2 --rules opensubdiv --boundary edges-and-corners
run_cli 0 "$saddle" "$WORK/edges.obj" --levels 2 --rules opensubdiv --boundary edges
same_file "$WORK/tag.obj" "$WORK/corners.obj" || fail "the interpolateboundary 1 tag is not 'edges and corners'"
same_file "$WORK/tag.obj" "$WORK/edges.obj" && fail "--boundary edges does not override the file's tag"
grep -qx 't interpolateboundary 1/0/0 2' "$WORK/edges.obj" || fail "the output does not record --boundary edges"
chaikin="$SHAPES/loop_chaikin0.obj"  # t creasemethod 0/0/1 normal
run_cli 0 "$chaikin" "$WORK/tag.obj" --levels 2 --rules opensubdiv
run_cli 0 "$chaikin" "$WORK/uniform.obj" --levels 2 --rules opensubdiv --crease-method uniform
run_cli 0 "$chaikin" "$WORK/chaikin.obj" --levels 2 --rules opensubdiv --crease-method chaikin
same_file "$WORK/tag.obj" "$WORK/uniform.obj" || fail "the creasemethod normal tag is not the uniform method"
same_file "$WORK/tag.obj" "$WORK/chaikin.obj" && fail "--crease-method chaikin does not override the file's tag"
grep -qx 't creasemethod 0/0/1 chaikin' "$WORK/chaikin.obj" || fail "the output does not record --crease-method chaikin"
# Hoppe94: sharpness 1 to 5 are all creases by default; a threshold of 3 keeps only those >= 3.
run_cli 0 "$chaikin" "$WORK/all.obj" --levels 1
run_cli 0 "$chaikin" "$WORK/some.obj" --levels 1 --crease-threshold 3
same_file "$WORK/all.obj" "$WORK/some.obj" && fail "--crease-threshold 3 changed nothing"
run_cli 0 "$chaikin" "$WORK/low.obj" --levels 1 --crease-threshold 1
same_file "$WORK/all.obj" "$WORK/low.obj" || fail "--crease-threshold 1 changed the surface though every sharpness is >= 1"

# Fed back in: one level on the output of one level is the same surface as two levels at once.
for rules in hoppe94 opensubdiv; do
  for shape in loop_icos_semisharp loop_cube_creases0 loop_chaikin0; do
    run_cli 0 "$SHAPES/$shape.obj" "$WORK/once.obj" --levels 1 --rules "$rules"
    run_cli 0 "$WORK/once.obj" "$WORK/twice.obj" --levels 1 --rules "$rules"
    run_cli 0 "$SHAPES/$shape.obj" "$WORK/direct.obj" --levels 2 --rules "$rules"
    check_same_points "$WORK/twice.obj" "$WORK/direct.obj" 1e-5
  done
done

# --limit: limit positions and unit normals, written as vn and referenced by every corner.
out="$WORK/limit.obj"
run_cli 0 "$SHAPES/loop_cube_creases0.obj" "$out" --levels 2 --rules opensubdiv --limit
[ "$(count_lines vn "$out")" -gt 0 ] || fail "$out: --limit wrote no vn"
awk '$1 == "f" { for (i = 2; i <= 4; ++i) if (split($i, p, "/") != 3 || p[3] == "") bad = 1 } END { exit bad }' "$out" \
  || fail "$out: a corner has no normal index: $(grep -m1 '^f' "$out")"
awk '$1 == "vn" { n = sqrt($2 * $2 + $3 * $3 + $4 * $4); if (n < 0.99999 || n > 1.00001) { print; exit 1 } }' "$out" \
  || fail "$out: a normal is not of unit length"
run_cli 0 "$SHAPES/loop_cube_creases0.obj" "$WORK/refined.obj" --levels 2 --rules opensubdiv
same_file "$out" "$WORK/refined.obj" && fail "--limit changed nothing"
run_cli 0 "$SHAPES/loop_pole8.obj" "$WORK/limit_no_uvs.obj" --levels 1 --limit
grep -q '^f [0-9]*//[0-9]* ' "$WORK/limit_no_uvs.obj" || fail "without UVs the faces should be f v//vn"

# --uv-interpolation: the modes give different UVs, the default is OpenSubdiv's (corners), and the mode is written.
for mode in none corners boundaries all; do
  run_cli 0 "$SHAPES/loop_fvar_bound0.obj" "$WORK/uv_$mode.obj" --levels 2 --rules opensubdiv --uv-interpolation "$mode"
  grep -q '^t facevaryinginterpolateboundary 1/0/0 ' "$WORK/uv_$mode.obj" || fail "uv_$mode.obj: the mode is not written"
done
run_cli 0 "$SHAPES/loop_fvar_bound0.obj" "$WORK/uv_default.obj" --levels 2 --rules opensubdiv
diff <(grep '^vt' "$WORK/uv_default.obj") <(grep '^vt' "$WORK/uv_corners.obj") >/dev/null || fail "the default UVs are not 'corners'"
diff <(grep '^vt' "$WORK/uv_none.obj") <(grep '^vt' "$WORK/uv_all.obj") >/dev/null && fail "'none' and 'all' gave the same UVs"
diff <(grep '^vt' "$WORK/uv_boundaries.obj") <(grep '^vt' "$WORK/uv_all.obj") >/dev/null && fail "'boundaries' and 'all' gave the same UVs"

# Holes and boundary "none": the faces are refined but not written; the vertices stay.
printf 't hole 1/0/0 3\n' | cat "$SHAPES/loop_icosahedron.obj" - >"$WORK/holed.obj"
run_cli 0 "$WORK/holed.obj" "$WORK/holed_out.obj" --levels 2 --rules opensubdiv
run_cli 0 "$SHAPES/loop_icosahedron.obj" "$WORK/whole_out.obj" --levels 2 --rules opensubdiv
[ "$(count_lines f "$WORK/holed_out.obj")" -eq $(( $(count_lines f "$WORK/whole_out.obj") - 16 )) ] \
  || fail "one hole at level 2 should leave out 16 triangles"
[ "$(count_lines v "$WORK/holed_out.obj")" -eq "$(count_lines v "$WORK/whole_out.obj")" ] || fail "a hole dropped vertices"
run_cli 0 "$SHAPES/loop_saddle_edgecorner.obj" "$WORK/none.obj" --levels 1 --boundary none
[ "$(count_lines f "$WORK/none.obj")" -lt 16 ] || fail "--boundary none kept every face of an open mesh"
grep -qx 't interpolateboundary 1/0/0 0' "$WORK/none.obj" || fail "--boundary none is not written"

finish
