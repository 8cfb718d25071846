#!/usr/bin/python3
"""Times each row in fresh processes beside the same work warm: what a user meets on the first call.

    PYTHONPATH=build/native /usr/bin/python3 scripts/bench_fresh.py [--runs 5] [--warm 20] [--only REGEX]

Python rows: a fresh `/usr/bin/python3` per run imports numpy and the package `loopsub` (import timed apart), loads
the mesh from .npy files and times the first call only, inside the process; the warm column is the same call in one
process, the median of `--warm` calls after `--warmups` untimed ones. CLI rows: `build/loopsub IN.obj OUT.obj ...
--threads 1 --stats` as a whole process, the wall time from outside and the CLI's own `--stats` (plan + evaluation),
whose warm column is the Python row of the same work; beside each --tessellate row, Bfr's one-shot job at the same
rate (build/loopsub_bfr_job, bench/bfr_job.cpp) as a whole process too. Peak resident memory, minor page faults and
user / kernel time come from `os.wait4` for each child; the Python rows also give the first call's own share (from
`getrusage` inside the child). Meshes: the benchmarks' icosphere (5,120 triangles, made here as
tests/support/meshes.cpp makes it) and assimp's WusonOBJ.obj (3,732 triangles, Debian's assimp-testmodels), each with
the UV layer of tests/support's add_uvs_with_seam for the UV rows, and written to an OBJ of v and f lines for the CLI.
Prints markdown tables. docs/benchmark.md, "Fresh processes
and first touches", has the numbers of a run.
"""
import argparse
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
WUSON_CANDIDATES = ("/usr/share/assimp/models/OBJ/WusonOBJ.obj",
                    "/usr/share/assimp-testmodels/models/OBJ/WusonOBJ.obj")

# The child: a fresh interpreter that imports, loads the mesh and times the first call (fresh) or, after warm-ups,
# the median of repeated calls (warm). Kept apart from this script so that the child imports nothing else first.
CHILD = r"""
import json, resource, sys, time
spec = json.loads(sys.argv[1])
def usage():
    r = resource.getrusage(resource.RUSAGE_SELF)
    return {"maxrss_kb": r.ru_maxrss, "minflt": r.ru_minflt, "majflt": r.ru_majflt, "utime": r.ru_utime,
            "stime": r.ru_stime}
t0 = time.perf_counter()
import numpy as np
import loopsub
t1 = time.perf_counter()
d = spec["dir"]
pos = np.load(d + "/positions.npy")
tri = np.load(d + "/triangles.npy")
if spec["kind"] == "uv":
    uv_indices = np.load(d + "/uv_indices.npy")
    uvs = np.load(d + "/uvs.npy")
n, level = len(pos), spec["level"]
def call():
    kind = spec["kind"]
    if kind == "subdivide":
        return loopsub.subdivide(pos, tri, levels=level)
    if kind == "plain":
        plan = loopsub.Plan(tri, n, levels=level)
        return plan, plan.evaluate(pos)
    if kind == "limit":
        plan = loopsub.Plan(tri, n, levels=level, limit_surface=True)
        return plan, plan.evaluate_with_normals(pos)
    if kind == "limit-compact":
        plan = loopsub.Plan(tri, n, levels=level, limit_surface=True)
        return plan, plan.evaluate_with_limit_normals(pos)
    if kind == "uv":
        plan = loopsub.Plan(tri, n, levels=level, face_varying_indices=[uv_indices])
        return plan, plan.evaluate(pos), plan.evaluate_face_varying(uvs, layer=0)
    if kind == "tessellate":
        tess = loopsub.Tessellation(tri, n, rate=level)
        return tess, tess.evaluate(pos)
    raise SystemExit("unknown kind " + kind)
before = usage()
t2 = time.perf_counter()
result = call()
t3 = time.perf_counter()
after = usage()
del result
out = {"import_ms": (t1 - t0) * 1e3, "first_ms": (t3 - t2) * 1e3, "before": before, "after": after}
if spec["warm"]:
    for _ in range(spec["warmups"]):
        result = call()
        del result
    times = []
    faults = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for _ in range(spec["warm"]):
        t = time.perf_counter()
        result = call()
        times.append((time.perf_counter() - t) * 1e3)
        del result
    out["warm_ms"] = times
    out["warm_minflt"] = (resource.getrusage(resource.RUSAGE_SELF).ru_minflt - faults) / spec["warm"]
print(json.dumps(out))
"""

KIND_NAMES = {"subdivide": "loopsub.subdivide", "plain": "Plan + evaluate",
              "limit": "Plan(limit_surface) + evaluate_with_normals",
              "limit-compact": "Plan(limit_surface) + evaluate_with_limit_normals",
              "uv": "Plan(face_varying_indices) + evaluate + evaluate_face_varying",
              "tessellate": "Tessellation(rate) + evaluate"}


def icosphere(splits=4):
    """tests/support/meshes.cpp's icosphere: the icosahedron on the unit sphere, each split putting the midpoints on
    the sphere, the children {a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}; float32 positions."""
    g = (1.0 + 5.0 ** 0.5) / 2.0
    s = 1.0 / (1.0 + g * g) ** 0.5
    base = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g), (0, -1, -g), (0, 1, -g),
            (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    positions = [tuple(float(np.float32(c * s)) for c in v) for v in base]
    triangles = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
                 (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
                 (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(splits):
        midpoint = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                m = [0.5 * (positions[a][k] + positions[b][k]) for k in range(3)]
                length = sum(c * c for c in m) ** 0.5
                midpoint[key] = len(positions)
                positions.append(tuple(float(np.float32(c / length)) for c in m))
            return midpoint[key]

        children = []
        for a, b, c in triangles:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            children += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        triangles = children
    return np.array(positions, np.float32), np.array(triangles, np.int32)


def read_obj(path):
    """Positions and triangles of an OBJ (v and f lines; polygons as fans), float32 / int32."""
    positions, triangles = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                positions.append([float(w) for w in words[1:4]])
            elif words[0] == "f":
                corners = [int(w.split("/")[0]) for w in words[1:]]
                corners = [c - 1 if c > 0 else len(positions) + c for c in corners]
                triangles += [(corners[0], corners[k], corners[k + 1]) for k in range(1, len(corners) - 1)]
    return np.array(positions, np.float32), np.array(triangles, np.int32)


def write_obj(path, positions, triangles):
    with open(path, "w") as f:
        f.writelines(f"v {x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in positions.tolist())
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles.tolist())


def uvs_with_seam(positions, triangles):
    """tests/support/meshes.cpp's add_uvs_with_seam: UVs from x, y (and z), the triangles whose centroid has x > 0
    using a second copy of every value, so that a seam runs through the mesh."""
    x, y, z = positions[:, 0], positions[:, 1], positions[:, 2]
    uvs = np.concatenate([np.stack([x + 0.3 * z, y - 0.2 * z], 1), np.stack([2.0 + 0.5 * x, 0.5 * y + 0.25 * z], 1)])
    right = positions[triangles][:, :, 0].astype(np.float64).sum(1) > 0
    indices = triangles + np.where(right, len(positions), 0)[:, None]
    uvs = uvs[:indices.max() + 1]  # one row per value of the layer, up to its largest index
    return np.ascontiguousarray(uvs, np.float32), np.ascontiguousarray(indices, np.int32)


def run_child(argv, env=None):
    """Runs a child to its end; returns (wall ms, stdout, its own rusage from wait4)."""
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        start = time.perf_counter()
        process = subprocess.Popen(argv, stdout=out, stderr=err, env=env)
        _, status, usage = os.wait4(process.pid, 0)
        wall = (time.perf_counter() - start) * 1e3
        process.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        text, error = out.read().decode(), err.read().decode()
    if process.returncode != 0:
        shown = " ".join("CHILD" if a == CHILD else a for a in argv)
        raise SystemExit(f"{shown} exited {process.returncode}: {error.strip()[-2000:]}")
    return wall, text, usage


def usage_fields(usage):
    return {"maxrss_mb": usage.ru_maxrss / 1024, "minflt": usage.ru_minflt, "majflt": usage.ru_majflt,
            "utime": usage.ru_utime, "stime": usage.ru_stime}


def python_row(args, env, mesh_dir, kind, level):
    spec = {"dir": mesh_dir, "kind": kind, "level": level, "warm": 0, "warmups": 0}
    runs = []
    for _ in range(args.runs):
        wall, text, usage = run_child([args.python, "-c", CHILD, json.dumps(spec)], env)
        child = json.loads(text)
        child["process"] = usage_fields(usage)
        child["wall_ms"] = wall
        runs.append(child)
    spec.update(warm=args.warm, warmups=args.warmups)
    _, text, _ = run_child([args.python, "-c", CHILD, json.dumps(spec)], env)
    warm = json.loads(text)
    return runs, warm["warm_ms"], warm["warm_minflt"]


def cli_row(args, obj, out_dir, flags):
    runs = []
    out = os.path.join(out_dir, "out.obj")
    for _ in range(args.runs):
        wall, text, usage = run_child([args.cli, obj, out, *flags, "--threads", "1", "--stats"])
        os.remove(out)
        stats = dict(word.split("=", 1) for word in text.split())
        runs.append({"wall_ms": wall, "core_ms": float(stats["topology_ms"]) + float(stats["evaluate_ms"]),
                     "topology_ms": float(stats["topology_ms"]), "evaluate_ms": float(stats["evaluate_ms"]),
                     "write_ms": float(stats.get("write_ms", "nan")),
                     "triangles_out": int(stats["triangles_out"]), "process": usage_fields(usage)})
    return runs


def bfr_row(args, obj, rate):
    """Bfr's one-shot tessellation (bench/bfr_job.cpp) as a whole process, each run beside none of ours."""
    runs = []
    for _ in range(args.runs):
        wall, text, usage = run_child([args.bfr_job, obj, str(rate)])
        stats = dict(word.split("=", 1) for word in text.split())
        runs.append({"wall_ms": wall, "core_ms": float(stats["factory_ms"]) + float(stats["evaluate_ms"]),
                     "process": usage_fields(usage)})
    return runs


def med_best(values, digits=1):
    return f"{statistics.median(values):.{digits}f} ({min(values):.{digits}f})"


def kernel_share(user, system):
    return f"{100 * system / (user + system):.0f} %" if user + system > 0 else "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=5, help="fresh processes per row (default 5)")
    parser.add_argument("--warm", type=int, default=20, help="timed warm calls in one process (default 20)")
    parser.add_argument("--warmups", type=int, default=3, help="untimed calls before them (default 3)")
    parser.add_argument("--levels", type=int, nargs="+", default=[3, 4])
    parser.add_argument("--rate", type=int, default=16, help="the tessellation rows' rate (default 16)")
    parser.add_argument("--only", default="", help="rows whose name matches this regular expression")
    parser.add_argument("--python", default="/usr/bin/python3")
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "loopsub"))
    parser.add_argument("--bfr-job", default=os.path.join(ROOT, "build", "loopsub_bfr_job"),
                        help="Bfr's one-shot tessellation, against the CLI's --tessellate rows (bench/bfr_job.cpp)")
    parser.add_argument("--module-dir", default=os.path.join(ROOT, "build", "native"),
                        help="where the built _loopsub module is (default build/native)")
    parser.add_argument("--wuson", default=next((p for p in WUSON_CANDIDATES if os.path.exists(p)), None),
                        help="the real model (default assimp's WusonOBJ.obj)")
    parser.add_argument("--json", help="also write every run's numbers here")
    args = parser.parse_args()

    modules = [f for f in os.listdir(args.module_dir) if f.startswith("_loopsub.") and f.endswith(".so")]
    if not modules:
        raise SystemExit(f"no _loopsub module in {args.module_dir}: build it first (docs/python.md)")
    work = tempfile.mkdtemp(prefix="bench_fresh.")
    try:
        measure(args, modules, work)
    finally:
        shutil.rmtree(work)


def measure(args, modules, work):
    # The package `loopsub` as installed: python/loopsub/__init__.py beside the built module.
    os.mkdir(os.path.join(work, "loopsub"))
    os.symlink(os.path.join(ROOT, "python", "loopsub", "__init__.py"), os.path.join(work, "loopsub", "__init__.py"))
    for module in modules:
        os.symlink(os.path.join(args.module_dir, module), os.path.join(work, "loopsub", module))
    env = dict(os.environ, PYTHONPATH=work)

    meshes = [("icosphere", icosphere(4))]
    if args.wuson:
        meshes.append(("Wuson", read_obj(args.wuson)))
    else:
        print("note: assimp's WusonOBJ.obj not found (apt-get install assimp-testmodels); icosphere only",
              file=sys.stderr)
    mesh_dirs = {}
    for name, (positions, triangles) in meshes:
        mesh_dir = os.path.join(work, name)
        os.mkdir(mesh_dir)
        uvs, uv_indices = uvs_with_seam(positions, triangles)
        for key, array in (("positions", positions), ("triangles", triangles), ("uvs", uvs),
                           ("uv_indices", uv_indices)):
            np.save(os.path.join(mesh_dir, key + ".npy"), array)
        write_obj(os.path.join(mesh_dir, "in.obj"), positions, triangles)
        mesh_dirs[name] = (mesh_dir, len(triangles))

    only = re.compile(args.only)
    results = {"python": [], "cli": []}
    warm_of = {}
    python_rows = [(name, kind, level) for name, _ in meshes for level in args.levels
                   for kind in ("subdivide", "plain", "limit", "limit-compact", "uv")]
    python_rows += [(name, "tessellate", args.rate) for name, _ in meshes]
    cli_rows = [(name, flags, kind, level) for name, _ in meshes
                for level in args.levels
                for flags, kind in ((["--levels", str(level)], "plain"),
                                    (["--levels", str(level), "--limit"], "limit-compact"))]
    cli_rows += [(name, ["--tessellate", str(args.rate)], "tessellate", args.rate) for name, _ in meshes]
    wanted = {(name, kind, level) for name, flags, kind, level in cli_rows
              if only.search(f"{name} loopsub {' '.join(flags)}")}
    for name, kind, level in python_rows:
        row = f"{name} {'rate' if kind == 'tessellate' else 'level'} {level}: {KIND_NAMES[kind]}"
        if not only.search(row) and (name, kind, level) not in wanted:
            continue
        runs, warm, warm_faults = python_row(args, env, mesh_dirs[name][0], kind, level)
        warm_of[(name, kind, level)] = statistics.median(warm)
        if only.search(row):
            results["python"].append({"row": row, "runs": runs, "warm_ms": warm, "warm_minflt": warm_faults})
        print(f"  {row}: first {med_best([r['first_ms'] for r in runs])} ms, warm "
              f"{statistics.median(warm):.2f} ms", file=sys.stderr)
    for name, flags, kind, level in cli_rows:
        row = f"{name} loopsub {' '.join(flags)}"
        if not only.search(row):
            continue
        runs = cli_row(args, os.path.join(mesh_dirs[name][0], "in.obj"), mesh_dirs[name][0], flags)
        results["cli"].append({"row": row, "runs": runs, "warm_ms": warm_of[(name, kind, level)],
                               "warm_row": KIND_NAMES[kind]})
        print(f"  {row}: wall {med_best([r['wall_ms'] for r in runs])} ms", file=sys.stderr)
        if kind == "tessellate" and os.path.exists(args.bfr_job):
            bfr = bfr_row(args, os.path.join(mesh_dirs[name][0], "in.obj"), level)
            results.setdefault("bfr", []).append({"row": f"{name} rate {level}", "runs": runs, "bfr": bfr})
            print(f"  {name} Bfr job rate {level}: wall {med_best([r['wall_ms'] for r in bfr])} ms", file=sys.stderr)

    print(f"\n{time.strftime('%Y-%m-%d %H:%M')}, {platform.node()}, {os.cpu_count()} cores, transparent huge pages "
          f"{_thp()}, {args.runs} fresh processes a row, warm: median of {args.warm} after {args.warmups}; "
          f"meshes: " + ", ".join(f"{name} {count:,} triangles" for name, (_, count) in mesh_dirs.items()) + "\n")
    if results["python"]:
        print("| Python, a fresh interpreter | first call ms, median (best) | warm ms | fresh / warm | import ms "
              "| peak MB (the call's rise) | minor faults (the call's) | kernel share of the call "
              "| faults a warm call |")
        print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for r in results["python"]:
            runs, warm = r["runs"], statistics.median(r["warm_ms"])
            first = [x["first_ms"] for x in runs]
            rise = [(x["after"]["maxrss_kb"] - x["before"]["maxrss_kb"]) / 1024 for x in runs]
            faults = [x["after"]["minflt"] - x["before"]["minflt"] for x in runs]
            user = sum(x["after"]["utime"] - x["before"]["utime"] for x in runs)
            system = sum(x["after"]["stime"] - x["before"]["stime"] for x in runs)
            print(f"| {r['row']} | {med_best(first)} | {warm:.2f} | {statistics.median(first) / warm:.1f}x "
                  f"| {statistics.median(x['import_ms'] for x in runs):.0f} "
                  f"| {statistics.median(x['process']['maxrss_mb'] for x in runs):.0f} "
                  f"({statistics.median(rise):.0f}) "
                  f"| {statistics.median(x['process']['minflt'] for x in runs):,.0f} "
                  f"({statistics.median(faults):,.0f}) "
                  f"| {kernel_share(user, system)} | {r['warm_minflt']:,.0f} |")
        print()
    if results["cli"]:
        print("| CLI, whole process (`--threads 1 --stats`) | wall ms, median (best) | its plan + evaluation ms "
              "| warm ms (Python, the same work) | fresh / warm | peak MB | minor faults | kernel share |")
        print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for r in results["cli"]:
            runs = r["runs"]
            core = [x["core_ms"] for x in runs]
            user = sum(x["process"]["utime"] for x in runs)
            system = sum(x["process"]["stime"] for x in runs)
            print(f"| {r['row']} | {med_best([x['wall_ms'] for x in runs])} | {med_best(core)} | {r['warm_ms']:.2f} "
                  f"| {statistics.median(core) / r['warm_ms']:.1f}x "
                  f"| {statistics.median(x['process']['maxrss_mb'] for x in runs):.0f} "
                  f"| {statistics.median(x['process']['minflt'] for x in runs):,.0f} | {kernel_share(user, system)} |")
    if results.get("bfr"):
        print("\n| One-shot tessellation, whole process | loopsub wall ms | its tessellation + evaluation "
              "| its OBJ write | Bfr's job wall ms | Bfr's factory + evaluation | Bfr / loopsub, whole "
              "| Bfr / loopsub, the work |")
        print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
        for r in results["bfr"]:
            ours, bfr = r["runs"], r["bfr"]
            wall, core = [x["wall_ms"] for x in ours], [x["core_ms"] for x in ours]
            bfr_wall, bfr_core = [x["wall_ms"] for x in bfr], [x["core_ms"] for x in bfr]
            print(f"| {r['row']} | {med_best(wall)} | {med_best(core)} "
                  f"| {med_best([x['write_ms'] for x in ours])} | {med_best(bfr_wall)} | {med_best(bfr_core)} "
                  f"| {statistics.median(bfr_wall) / statistics.median(wall):.2f}x "
                  f"| {statistics.median(bfr_core) / statistics.median(core):.2f}x |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(results, f, indent=1)


def _thp():
    try:
        with open("/sys/kernel/mm/transparent_hugepage/enabled") as f:
            return re.search(r"\[(\w+)\]", f.read()).group(1)
    except (OSError, AttributeError):
        return "unknown"


if __name__ == "__main__":
    main()
