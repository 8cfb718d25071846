# A "book" of 100 triangles on one edge (fins or cards glued along an edge) tessellated at rates between levels, where
# every triangle is refined locally beside the non-manifold edge: each in its own fans, not all the pages, so that it
# runs in a few tens of MB and well under a second (it took 17 GB and 103 s at rate 3). Run under a cap of 768 MiB of
# address space and 60 s, which a run that grows with a power of the pages passes; where the binary is no native
# executable (scripts/cross.sh runs these tests through wine or qemu, whose own reservations the cap would refuse),
# without the cap, checking the result only. The same with the spine tagged, which took the path of all the pages.
source "$(dirname "$0")/cli_lib.sh"

book="$WORK/book.obj"
python3 - "$book" <<'PY'
import math, sys
pages = 100
with open(sys.argv[1], "w") as f:
    f.write("v 0 0 0\nv 0 0 1\n")
    for k in range(pages):
        f.write(f"v {math.cos(2 * math.pi * k / pages):.6f} {math.sin(2 * math.pi * k / pages):.6f} 0.5\n")
    for k in range(pages):
        f.write(f"f 1 2 {k + 3}\n")
PY

# The caps below hold where the binary is this machine's and unsanitized: a cross-built one runs under wine or qemu,
# which they would cut short, and AddressSanitizer's shadow memory needs the address space they take away (and makes
# the resident peak no measure of the core's).
native=0
[ "$(head -c 4 "$LOOPSUB" | od -An -c | tr -d ' ')" = '177ELF' ] && ! grep -q __asan_init "$LOOPSUB" && native=1
# tessellate WHAT MESH RATES: each rate under both rule sets, capped in memory and time where they hold; the output
# checked.
tessellate() {
  local what=$1 mesh=$2 rate rules out code
  shift 2
  for rules in opensubdiv hoppe94; do
    for rate in "$@"; do
      out="$WORK/$(basename "$mesh" .obj).$rules.$rate.obj"
      if ((native)); then
        (ulimit -v $((768 * 1024)) && exec timeout 60 "$LOOPSUB" "$mesh" "$out" --tessellate "$rate" --rules "$rules") \
          >"$WORK/stdout" 2>"$WORK/stderr"
      else
        "$LOOPSUB" "$mesh" "$out" --tessellate "$rate" --rules "$rules" >"$WORK/stdout" 2>"$WORK/stderr"
      fi
      code=$?
      if ((code != 0)); then
        fail "$what at --tessellate $rate --rules $rules exited with $code (124: past 60 s): $(head -c 300 "$WORK/stderr")"
        continue
      fi
      # The vertices, the points inside the spine (once) and the pages' 200 other edges, and inside the 100 triangles.
      check_valid_obj "$out" $((102 + 201 * (rate - 1) + 50 * (rate - 1) * (rate - 2))) $((100 * rate * rate))
    done
  done
}

tessellate "the book" "$book" 3 5 7
# The spine tagged (infinitely sharp, as a non-manifold edge is whatever its tag) and a page's edges semi-sharp: each
# triangle still refines its own fans (the tag took 204 MB and 87 s at rate 3, 251 s at rate 7).
tagged="$WORK/tagged.obj"
{ cat "$book"; printf 't crease 2/1/0 0 1 10\nt crease 2/1/0 0 2 2.5\n'; } >"$tagged"
tessellate "the tagged book" "$tagged" 3 7
# The resident peak, where GNU time is there to tell it: under 300 MB (under the same cap).
if ((native)) && [ -x /usr/bin/time ]; then
  (ulimit -v $((768 * 1024)) && exec /usr/bin/time -f '%M' -o "$WORK/peak" timeout 60 "$LOOPSUB" "$book" \
    "$WORK/peak.obj" --tessellate 3 --rules opensubdiv) >/dev/null 2>&1 ||
    fail "the book at --tessellate 3 under /usr/bin/time failed"
  peak=$(tail -1 "$WORK/peak")
  ((peak < 300 * 1024)) || fail "the book at --tessellate 3 peaked at $peak KB resident, more than 300 MB"
  (ulimit -v $((768 * 1024)) && exec /usr/bin/time -f '%M' -o "$WORK/peak" timeout 60 "$LOOPSUB" "$tagged" \
    "$WORK/peak.obj" --tessellate 7 --rules opensubdiv) >/dev/null 2>&1 ||
    fail "the tagged book at --tessellate 7 under /usr/bin/time failed"
  peak=$(tail -1 "$WORK/peak")
  ((peak < 300 * 1024)) || fail "the tagged book at --tessellate 7 peaked at $peak KB resident, more than 300 MB"
fi
finish
