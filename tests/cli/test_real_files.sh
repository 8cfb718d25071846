# OBJ files written by other tools (Debian's assimp-testmodels, which scripts/setup.sh installs): lines and points
# skipped with a note, faces with and without texture coordinates mixed, a concave 66-gon around a hole, n-gons;
# each subdivides to the counts its polygons predict, and a UTF-16 file is refused by name.
source "$(dirname "$0")/cli_lib.sh"

models=/usr/share/assimp/models/OBJ
[ -d "$models" ] || { fail "$models is missing: install assimp-testmodels (scripts/setup.sh does)"; finish; }
out="$WORK/out.obj"

# Vertices, edges of the triangulated polygons (their sides plus n - 3 diagonals each) and triangles of a file.
input_counts() {
  local sides
  sides=$(count_edges "$1")
  awk -v sides="$sides" '$1 == "v" { v++ } $1 == "f" { n = NF - 1; t += n - 2; d += n - 3 }
                         END { print v, sides + d, t }' "$1"
}

for name in testmixed regr01 concave_polygon spider WusonOBJ; do
  run_cli 0 "$models/$name.obj" "$out" --levels 1
  read -r v e t <<<"$(input_counts "$models/$name.obj")"
  read -r want_v want_t <<<"$(expected_counts "$v" "$e" "$t" 1)"
  check_valid_obj "$out" "$want_v" "$want_t"
done

run_cli 0 "$models/testmixed.obj" "$out" --levels 1
expect_stderr "skipped 6 'l' statements (polylines, not surfaces)"
run_cli 0 "$models/regr01.obj" "$out" --levels 1
expect_stderr "faces without texture coordinates got (0, 0), as other faces have them"
run_cli 0 "$models/concave_polygon.obj" "$out" --levels 1
expect_stderr "triangulated 1 polygon(s) with more than 3 corners"
run_cli 1 "$models/box_UTF16BE.obj" "$out" --levels 1
expect_stderr "box_UTF16BE.obj:1: the file is not plain text"

finish
