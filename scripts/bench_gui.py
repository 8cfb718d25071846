"""Interactive latency in Blender's interface: Loop Subdivision against Subdivision Surface on a ~100k-triangle cage,
as an artist feels it while editing. scripts/bench_gui.sh runs it (Blender 3.4.1 under Xvfb, Mesa's software
OpenGL), one configuration per Blender process, and scripts/bench_gui_table.py makes the table:

    blender --factory-startup -p 0 0 1600 1000 --python scripts/bench_gui.py -- \\
        --addon-dir build/packaged-addon/loop_subdivision --config loop:2 --json OUT.json [--repeat N]

--config is loop:LEVEL (the add-on, rules OPENSUBDIV), subsurf-gpu:LEVEL (Subdivision Surface with Blender's default
GPU subdivision) or subsurf-cpu:LEVEL (GPU subdivision off); both modifiers with their defaults, Use Limit Surface
on (Subdivision Surface at quality 3). Measured, each time from a still viewport:

- redraw, still: a redraw asked for with nothing changed; AA sample: one sample of Solid shading's viewport
  anti-aliasing (8 by default: after every change the viewport draws the scene again for each sample while nothing
  changes), i.e. what a draw of the subdivided mesh costs;
- edit -> first draw: from an edit of the cage (a round patch raised, mesh.update()) to the end of the next viewport
  draw, its final shading on both sides (Loop Subdivision writes the limit normals on every update); edit ->
  evaluated is the part before the draw (the add-on's depsgraph handler included);
- edit -> viewport still: the end of the last draw (anti-aliasing samples) before the viewport goes quiet;
- longest stall during a drag: 30 edits from a timer at ~30 Hz with a 0.5 s hold after the 15th (an artist holding
  still mid-drag); the longest time the main thread did not get back to its event loop, seen as the largest gap
  between ticks of a 5 ms probe timer, from the first edit to the draw after the last.

Everything runs from timers on the main thread, as edits from the interface do, so that Blender's own event loop
evaluates the depsgraph, runs the add-on's handlers, and draws, in the order it does for an artist.
"""
import argparse
import bisect
import json
import math
import os
import statistics
import subprocess
import sys
import time
import traceback

import bpy
import bmesh
import gpu
import numpy as np
from mathutils import Euler, Vector

try:
    import bgl  # deprecated from 3.5 on, still there in 3.4: its glFinish makes a draw's timestamp its end
except ImportError:
    bgl = None

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "blender"))
import blender_test_support as support  # noqa: E402  (loads the packaged add-on as the tests do)

now = time.perf_counter

DRAG_EDITS = 30
DRAG_INTERVAL = 1 / 30
HOLD_SECONDS = 0.5
PROBE_SECONDS = 0.005
IDLE_SECONDS = 0.4  # quiet time (no draw, no evaluation) before each measured edit
IDLE_REDRAWS = 3
# For any single expected draw: Subdivision Surface's first draw of this cage at level 2 (its topology built on the
# spot) takes tens of seconds here.
WAIT_SECONDS = 600.0
# A drag whose every edit takes seconds stops once this is spent (after the hold): its stall is plain by then, and a
# full one would take many minutes.
DRAG_BUDGET_SECONDS = 60.0


def arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser()
    parser.add_argument("--addon-dir", required=True)
    parser.add_argument("--config", required=True, help="loop:LEVEL, subsurf-gpu:LEVEL or subsurf-cpu:LEVEL")
    parser.add_argument("--repeat", type=int, default=1, help="edits and drags measured in this process")
    parser.add_argument("--grid", type=int, default=224,
                        help="quads per side of the cage before triangulation: 224 makes 100,352 triangles")
    parser.add_argument("--json", required=True, help="the samples are written here")
    parser.add_argument("--screenshot", default="", help="the X screen, taken once the first edit is drawn")
    args, _ = parser.parse_known_args(argv)
    kind, level = args.config.split(":")
    if kind not in ("loop", "subsurf-gpu", "subsurf-cpu"):
        parser.error(f"unknown configuration {args.config}")
    args.kind, args.level = kind, int(level)
    return args


class Timeline:
    """Timestamps of what the main thread did, on one perf_counter clock."""

    def __init__(self):
        self.draws = []  # ends of 3D-viewport draws (after glFinish: software GL rasterises in its own threads)
        self.ticks = []  # probe timer ticks: the main thread was back in its event loop
        self.evaluations = []  # depsgraph_update_post, after the add-on's own handler (registered before ours)

    @staticmethod
    def first_after(times, t):
        i = bisect.bisect_right(times, t)
        return times[i] if i < len(times) else None

    @staticmethod
    def last_before(times, t):
        i = bisect.bisect_left(times, t)
        return times[i - 1] if i else None


timeline = Timeline()


def _on_draw():
    if bgl is not None:
        bgl.glFinish()
    timeline.draws.append(now())


def _probe():
    timeline.ticks.append(now())
    return PROBE_SECONDS


def _on_evaluated(*_):
    timeline.evaluations.append(now())


def view3d():
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                return window, area, next(region for region in area.regions if region.type == 'WINDOW')
    raise RuntimeError("no 3D viewport in the startup screen")


def frame_view():
    """Solid shading, a three-quarter view in which the cage fills most of the viewport, no smooth-view animation
    (it would add draws of its own)."""
    _, area, _ = view3d()
    space = area.spaces.active
    space.shading.type = 'SOLID'
    r3d = space.region_3d
    r3d.view_perspective = 'PERSP'
    r3d.view_location = Vector((0.0, 0.0, 0.0))
    r3d.view_rotation = Euler((math.radians(55), 0.0, math.radians(30))).to_quaternion()
    r3d.view_distance = 3.2
    bpy.context.preferences.view.smooth_view = 0


class Cage:
    """A UV-mapped grid of cuts^2 quads, triangulated (224: 100,352 triangles), gently waved so that shading shows
    its normals, shaded smooth; edits raise a round patch of it with a smooth falloff, as a proportional grab does."""

    def __init__(self, name, cuts):
        bm = bmesh.new()
        bm.loops.layers.uv.new("UVMap")
        bmesh.ops.create_grid(bm, x_segments=cuts, y_segments=cuts, size=1.0, calc_uvs=True)
        for vertex in bm.verts:
            vertex.co.z = 0.06 * math.sin(5.0 * vertex.co.x) * math.cos(4.0 * vertex.co.y)
        self.obj = support.shade_smooth(support.object_from_bmesh(name, bm))
        mesh = self.obj.data
        self.rest = np.empty(len(mesh.vertices) * 3, dtype=np.float32)
        mesh.vertices.foreach_get("co", self.rest)
        self.rest = self.rest.reshape(-1, 3)
        distance = np.hypot(self.rest[:, 0] - 0.2, self.rest[:, 1] - 0.1) / 0.1
        self.patch = np.flatnonzero(distance < 1.0)
        self.falloff = (1.0 - distance[self.patch] ** 2) ** 2
        self.triangles = len(mesh.polygons)

    def raise_patch(self, height):
        co = self.rest.copy()
        co[self.patch, 2] += height * self.falloff
        self.obj.data.vertices.foreach_set("co", co.ravel())
        self.obj.data.update()


def result_mesh(obj, live):
    """The mesh that Loop Subdivision's helper object carries: the result it writes the limit normals into."""
    stack = live.stack
    helper = getattr(stack, "helper_of", None) or stack.helper  # stack.helper before the add-on's 8dd1d21
    return helper(obj, stack.entry(obj), create=False).data


def quiet_since():
    """When the main thread last drew or evaluated."""
    return max([0.0] + timeline.draws[-1:] + timeline.evaluations[-1:])


# The measurement is a generator run by a timer: it yields how long to wait before it goes on, so that the event loop
# keeps evaluating and drawing in between, as it does for an artist.

def until(condition, timeout, poll=0.01):
    deadline = now() + timeout
    while not condition():
        if now() > deadline:
            return False
        yield poll
    return True


def until_idle():
    def idle():
        return now() - quiet_since() > IDLE_SECONDS
    if not (yield from until(idle, WAIT_SECONDS)):
        raise RuntimeError(f"the interface did not become idle within {WAIT_SECONDS} s")


def until_drawn_after(t):
    if not (yield from until(lambda: Timeline.first_after(timeline.draws, t) is not None, WAIT_SECONDS)):
        raise RuntimeError("no viewport draw after an edit")
    return Timeline.first_after(timeline.draws, t)


def longest_gap(start, end):
    """The longest time between two probe ticks (or the window's ends) within [start, end]: (gap, from, to)."""
    ticks = [start] + [t for t in timeline.ticks if start < t < end] + [end]
    return max((b - a, a, b) for a, b in zip(ticks, ticks[1:]))


def screenshot(path):
    """The whole X screen (Xvfb's): the check that the viewport shows the subdivided cage."""
    try:
        subprocess.run(["import", "-window", "root", path], check=True, timeout=60)
    except (OSError, subprocess.SubprocessError) as problem:
        print(f"gui-bench screenshot failed: {problem}", flush=True)


def log(what, value):
    """Progress on the log that scripts/bench_gui.sh keeps: a run takes minutes."""
    def rounded(x):
        if isinstance(x, float):
            return round(x, 1)
        if isinstance(x, dict):
            return {k: rounded(v) for k, v in x.items()}
        if isinstance(x, (list, tuple)):
            return [rounded(v) for v in x]
        return x
    print(f"gui-bench {what}: {json.dumps(rounded(value))}", flush=True)


def measure(args, live):
    loop = args.kind == "loop"
    result = {"config": args.config, "kind": args.kind, "level": args.level, "blender": bpy.app.version_string,
              "renderer": f"{gpu.platform.renderer_get()} ({gpu.platform.version_get()})",
              "viewport_aa": bpy.context.preferences.system.viewport_aa, "cpu_count": os.cpu_count(),
              "load": [os.getloadavg()[0]]}
    bpy.context.preferences.system.use_gpu_subdivision = args.kind == "subsurf-gpu"
    frame_view()
    support.clear_scene()  # the startup file's cube, camera and light
    cage = Cage("Cage", args.grid)
    if loop:
        window, area, region = view3d()
        with bpy.context.temp_override(window=window, area=area, region=region, object=cage.obj,
                                       active_object=cage.obj):
            bpy.ops.object.loop_subdivision_add(levels=args.level, render_levels=args.level, rules='OPENSUBDIV')
        # Loop makes 4 triangles of each per level.
        result["drawn_triangles"] = cage.triangles * 4 ** args.level
    else:
        modifier = cage.obj.modifiers.new("Subdivision", 'SUBSURF')
        modifier.levels = modifier.render_levels = args.level  # quality 3, Use Limit Surface on: the defaults
        # Catmull-Clark makes 3 quads of a triangle, then 4 of each quad per level; each quad draws as 2 triangles.
        result["drawn_triangles"] = cage.triangles * 3 * 4 ** (args.level - 1) * 2
    result["cage_triangles"], result["patch_vertices"] = cage.triangles, len(cage.patch)
    _, _, region = view3d()

    # Warm-up: the first edit builds Loop's plan and Blender's subdivision topology, which a drag does not repeat.
    yield from until_idle()
    t = now()
    cage.raise_patch(0.02)
    drawn = yield from until_drawn_after(t)
    result["warm_up_first_draw_ms"] = [1e3 * (drawn - t)]
    if loop:
        # What the viewport draws is the object's evaluated mesh: the entry's output, not the cage.
        evaluated = cage.obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data
        result["evaluated_triangles"] = len(evaluated.polygons)
        result["limit_normals_drawn"] = result_mesh(cage.obj, live).has_custom_normals
    yield from until_idle()
    if args.screenshot:
        screenshot(args.screenshot)
    log("warm-up", {k: v for k, v in result.items() if "triangles" in k or "normals" in k or "warm" in k})

    # A redraw with nothing changed, asked for as a click or a hover would.
    idle = []
    for _ in range(IDLE_REDRAWS):
        yield from until_idle()
        t = now()
        region.tag_redraw()
        idle.append((yield from until_drawn_after(t)) - t)
    result["idle_redraw_ms"] = [1e3 * x for x in idle]

    # One edit, then hands off.
    first, evaluated, still, sample_draws = [], [], [], []
    for i in range(args.repeat):
        yield from until_idle()
        t = now()
        cage.raise_patch(0.03 + 0.01 * (i % 2))
        drawn = yield from until_drawn_after(t)
        first.append(drawn - t)
        evaluated.append((Timeline.last_before(timeline.evaluations, drawn) or drawn) - t)
        yield from until_idle()
        draws = [d for d in timeline.draws if d > t]
        still.append(draws[-1] - t)
        # Back-to-back redraws with no evaluation between them: what one draw of the scene costs.
        sample_draws += [b - a for a, b in zip(draws, draws[1:])
                         if not any(a < x < b for x in timeline.evaluations)]
    result["edit_first_draw_ms"] = [1e3 * x for x in first]
    result["edit_evaluated_ms"] = [1e3 * x for x in evaluated]
    result["edit_still_ms"] = [1e3 * x for x in still]
    result["sample_draw_ms"] = [1e3 * x for x in sample_draws]
    log("edits", {k: v for k, v in result.items() if k.endswith("_ms")})

    # Drags: 30 edits from this timer, 1/30 s apart, with a hold after the 15th.
    drags = result["drags"] = []
    for _ in range(args.repeat):
        yield from until_idle()
        edits = []
        for k in range(DRAG_EDITS):
            edits.append(now())
            cage.raise_patch(0.15 * (k + 1) / DRAG_EDITS)
            if now() - edits[0] > DRAG_BUDGET_SECONDS and k >= DRAG_EDITS // 2:
                break
            yield HOLD_SECONDS if k == DRAG_EDITS // 2 - 1 else DRAG_INTERVAL
        end = yield from until_drawn_after(edits[-1])
        gap, gap_from, gap_to = longest_gap(edits[0], end)
        latencies = []
        for k, t in enumerate(edits):
            drawn = Timeline.first_after(timeline.draws, t)
            following = edits[k + 1] if k + 1 < len(edits) else math.inf
            if drawn is not None and drawn < following:
                latencies.append(drawn - t)
        drag = {
            "edits": len(edits),
            "longest_stall_ms": 1e3 * gap,
            "longest_stall_at_ms": [1e3 * (gap_from - edits[0]), 1e3 * (gap_to - edits[0])],
            "duration_ms": 1e3 * (end - edits[0]),
            "edit_draw_median_ms": 1e3 * statistics.median(latencies) if latencies else None,
        }
        if len(edits) > DRAG_EDITS // 2:
            hold_from, hold_to = edits[DRAG_EDITS // 2 - 1], edits[DRAG_EDITS // 2]
            drag["hold_ms"] = 1e3 * (hold_to - hold_from)
            drag["edit_after_hold_first_draw_ms"] = 1e3 * (Timeline.first_after(timeline.draws, hold_to) - hold_to)
        drags.append(drag)
        log("drag", drag)
    yield from until_idle()
    result["load"].append(os.getloadavg()[0])
    with open(args.json, "w") as out:
        json.dump(result, out, indent=1)
    if args.screenshot:
        # After the measurements: a close-up with the wireframe overlay, where the result's triangles (4 of each
        # cage triangle per level for Loop, 3 quads and then 4 for Subdivision Surface) can be counted.
        _, area, region = view3d()
        area.spaces.active.overlay.show_wireframes = True
        r3d = area.spaces.active.region_3d
        r3d.view_location = Vector((0.2, 0.1, 0.0))
        r3d.view_distance = 0.12
        t = now()
        region.tag_redraw()
        yield from until_drawn_after(t)
        yield from until_idle()
        screenshot(args.screenshot.replace(".png", "-wireframe.png"))


def main():
    args = arguments()
    # Factory settings open the Quick Setup splash over the viewport: it would sit in every draw and screenshot.
    bpy.context.preferences.view.show_splash = False
    package = support.load_addon()
    live = package.live
    bpy.types.SpaceView3D.draw_handler_add(_on_draw, (), 'WINDOW', 'POST_PIXEL')
    bpy.app.handlers.depsgraph_update_post.append(_on_evaluated)
    bpy.app.timers.register(_probe, first_interval=PROBE_SECONDS)
    steps = measure(args, live)

    def drive():
        try:
            return next(steps)
        except StopIteration:
            bpy.ops.wm.quit_blender()
        except Exception:  # noqa: BLE001  a timer's exception would only be printed, and the run would hang
            traceback.print_exc()
            sys.stdout.flush()
            sys.stderr.flush()
            os._exit(1)
        return None

    # The startup screen draws before timers run; start once it is up.
    bpy.app.timers.register(drive, first_interval=1.0)


main()
