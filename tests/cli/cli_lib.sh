# Helpers shared by the CLI tests. ctest runs each as: bash test_NAME.sh <path-to-loopsub> <peer-shapes-dir>
# A test calls check_* / run_cli as often as it likes, then `finish`, which exits non-zero if any check failed.
set -u

if [ $# -ne 2 ]; then
  echo "usage: bash $0 <path-to-loopsub> <peer-shapes-dir>" >&2
  exit 2
fi
LOOPSUB=$1
SHAPES=$2
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
failures=0

fail() {
  echo "FAIL: $*" >&2
  failures=$((failures + 1))
}

# require_shapes: a test that reads OpenSubdiv's shapes ends here as skipped (exit 77, ctest's "Not Run") with the
# reason when they are missing, in a clone that does not sit beside the team's shared folder.
require_shapes() {
  if [ ! -d "$SHAPES" ]; then
    echo "$(basename "$0"): skipped: OpenSubdiv's Loop shapes are not in $SHAPES (clone beside the team's shared folder)"
    exit 77
  fi
}

finish() {
  if ((failures > 0)); then
    echo "$(basename "$0"): $failures check(s) failed" >&2
    exit 1
  fi
  echo "$(basename "$0"): all checks passed"
}

# run_cli EXPECTED_EXIT_CODE ARGS...: runs loopsub with stdout and stderr in $WORK/stdout and $WORK/stderr.
run_cli() {
  local expected=$1
  shift
  "$LOOPSUB" "$@" >"$WORK/stdout" 2>"$WORK/stderr"
  local code=$?
  # A Windows build writes its console lines with CR LF (scripts/cross.sh windows runs these tests under wine).
  sed -i 's/\r$//' "$WORK/stdout" "$WORK/stderr"
  if ((code >= 128)); then
    fail "loopsub $* crashed (exit code $code): $(cat "$WORK/stderr")"
  elif ((code != expected)); then
    fail "loopsub $* exited with $code, expected $expected; stderr: $(cat "$WORK/stderr")"
  fi
  return 0
}

# expect_stderr TEXT: the last run's stderr contains TEXT (a fixed string).
expect_stderr() {
  grep -qF -- "$1" "$WORK/stderr" || fail "stderr of the last run lacks '$1': $(cat "$WORK/stderr")"
}

# Number of lines of FILE that start with the OBJ keyword KEYWORD.
count_lines() {
  grep -c "^$1 " "$2"
}

# Number of distinct undirected edges of the `f` lines of an OBJ file (vertex part of each corner).
count_edges() {
  awk '$1 == "f" {
         n = NF - 1
         for (i = 2; i <= NF; i++) { split($i, c, "/"); v[i - 1] = c[1] }
         for (i = 1; i <= n; i++) {
           a = v[i] + 0; b = v[i % n + 1] + 0
           key = a < b ? a " " b : b " " a
           if (!(key in seen)) { seen[key] = 1; edges++ }
         }
       }
       END { print edges + 0 }' "$1"
}

# check_valid_obj FILE VERTICES TRIANGLES: exactly that many v and f lines, every f a triangle whose indices
# (and vt indices, if any) are in range, every coordinate a finite number.
check_valid_obj() {
  local file=$1 vertices=$2 triangles=$3
  local got_v got_f
  got_v=$(count_lines v "$file")
  got_f=$(count_lines f "$file")
  [ "$got_v" -eq "$vertices" ] || fail "$file: $got_v vertices, expected $vertices"
  [ "$got_f" -eq "$triangles" ] || fail "$file: $got_f triangles, expected $triangles"
  local problem
  problem=$(awk '
    $1 == "v"  { nv++; if (NF != 4) { print "line " NR ": v needs 3 coordinates"; exit }
                 for (i = 2; i <= 4; i++) if ($i !~ /^-?[0-9.]+(e[-+]?[0-9]+)?$/) { print "line " NR ": bad coordinate " $i; exit } }
    $1 == "vt" { nvt++ }
    $1 == "f"  { if (NF != 4) { print "line " NR ": not a triangle"; exit }
                 for (i = 2; i <= 4; i++) {
                   split($i, c, "/")
                   if (c[1] < 1 || c[1] > nv) { print "line " NR ": vertex index " c[1] " out of range"; exit }
                   if ((2 in c) && c[2] != "" && (c[2] < 1 || c[2] > nvt)) { print "line " NR ": texture index " c[2] " out of range"; exit }
                 } }' "$file")
  [ -z "$problem" ] || fail "$file: $problem"
}

# expected_counts V E F LEVELS: prints the vertex and triangle counts after LEVELS levels (each edge adds a
# vertex and splits in two, each triangle adds three inner edges and splits in four).
expected_counts() {
  local v=$1 e=$2 f=$3 levels=$4 l
  for ((l = 0; l < levels; l++)); do
    v=$((v + e))
    e=$((2 * e + 3 * f))
    f=$((4 * f))
  done
  echo "$v $f"
}

# check_same_points A B TOLERANCE: the v lines of two OBJ files are the same point set (each point of A has a
# point of B within TOLERANCE in every coordinate, and the counts match). Vertex order may differ.
check_same_points() {
  local a=$1 b=$2 tolerance=$3
  local result
  result=$(awk -v tol="$tolerance" '
    FNR == 1 { file++ }
    $1 == "v" && file == 1 { n++; ax[n] = $2; ay[n] = $3; az[n] = $4 }
    $1 == "v" && file == 2 { m++; bx[m] = $2; by[m] = $3; bz[m] = $4 }
    function abs(x) { return x < 0 ? -x : x }
    END {
      if (n != m) { print "vertex counts differ: " n " and " m; exit }
      for (i = 1; i <= n; i++) {
        found = 0
        for (j = 1; j <= m && !found; j++)
          if (abs(ax[i] - bx[j]) <= tol && abs(ay[i] - by[j]) <= tol && abs(az[i] - bz[j]) <= tol) found = 1
        if (!found) { print "vertex " i " (" ax[i] " " ay[i] " " az[i] ") has no match"; exit }
      }
    }' "$a" "$b")
  [ -z "$result" ] || fail "$a vs $b: $result"
}
