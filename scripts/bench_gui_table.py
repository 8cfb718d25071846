"""The markdown table of scripts/bench_gui.sh: medians over the JSON files that scripts/bench_gui.py wrote, one per
Blender process (a configuration in one round). Plain Python, no Blender.

    python3 scripts/bench_gui_table.py RESULT.json...
"""
import json
import os
import statistics
import sys

ORDER = ("loop", "subsurf-gpu", "subsurf-cpu")
NAMES = {"loop": "Loop Subdivision", "subsurf-gpu": "Subdivision Surface, GPU subdivision on",
         "subsurf-cpu": "Subdivision Surface, GPU subdivision off"}
SHORT = {"loop": "Loop Subdivision", "subsurf-gpu": "Subdivision Surface, GPU on",
         "subsurf-cpu": "Subdivision Surface, GPU off"}


def median(values):
    values = [v for v in values if v is not None]
    return statistics.median(values) if values else None


def ms(value):
    return "-" if value is None else f"{value:,.0f}"


def merged(paths):
    """The processes' samples, per configuration: lists concatenated, in the order the runs came."""
    configs = {}
    for path in paths:
        with open(path) as file:
            run = json.load(file)
        into = configs.setdefault((ORDER.index(run["kind"]), run["level"]), {"runs": 0})
        into["runs"] += 1
        for key, value in run.items():
            if isinstance(value, list):
                into.setdefault(key, []).extend(value)
            else:
                into.setdefault(key, value)
    return [configs[key] for key in sorted(configs)]


def table(configs):
    first = configs[0]
    loads = [x for config in configs for x in config["load"]]
    runs = sorted({config["runs"] for config in configs})
    lines = [
        f"Blender {first['blender']}, {first['renderer']}, window 1600x1000 under Xvfb, {first['cpu_count']} cores "
        f"(1-minute load average {min(loads):.1f}-{max(loads):.1f}, Blender's own threads included); cage: "
        f"{first['cage_triangles']:,} triangles (grid, triangulated), UV-mapped, shaded smooth, "
        f"{first['patch_vertices']} vertices moved per edit; Solid shading, viewport anti-aliasing "
        f"{first['viewport_aa']} samples (defaults). Medians over {'/'.join(map(str, runs))} rounds, each "
        f"configuration in a fresh Blender, in ms.", "",
        "| Blender | modifier | level | triangles drawn | redraw, still / AA sample | edit → first draw | "
        "edit → viewport still | longest stall during drag | drag: edit → draw |",
        "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"]
    for c in configs:
        drags = c["drags"]
        lines.append(
            f"| {c['blender']} | {NAMES[c['kind']]} | {c['level']} | {c['drawn_triangles']:,} | "
            f"{ms(median(c['idle_redraw_ms']))} / {ms(median(c['sample_draw_ms']))} | "
            f"{ms(median(c['edit_first_draw_ms']))} | "
            f"{ms(median(c['edit_still_ms']))} | {ms(median([d['longest_stall_ms'] for d in drags]))} | "
            f"{ms(median([d['edit_draw_median_ms'] for d in drags]))} |")
    lines += [
        "", "Details (medians; a drag stops once past its hold and 60 s).", "",
        "| modifier | level | first edit (warm-up) → draw | edit → evaluated | drag: edits / length | "
        "edit after the hold → draw |",
        "| --- | ---: | ---: | ---: | ---: | ---: |"]
    for c in configs:
        drags = c["drags"]
        held = [d for d in drags if "hold_ms" in d]
        lines.append(
            f"| {SHORT[c['kind']]} | {c['level']} | {ms(median(c['warm_up_first_draw_ms']))} | "
            f"{ms(median(c['edit_evaluated_ms']))} | "
            f"{median([d['edits'] for d in drags]):.0f} / {ms(median([d['duration_ms'] for d in drags]))} | "
            f"{ms(median([d['edit_after_hold_first_draw_ms'] for d in held]))} |")
    return "\n".join(lines)


if __name__ == "__main__":
    paths = [path for path in sys.argv[1:] if os.path.getsize(path)]
    if not paths:
        sys.exit("bench_gui_table: no results")
    print(table(merged(paths)))
