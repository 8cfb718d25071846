"""The layers of native/src (docs/architecture.md, "Layers") include only the layers below them: a lower layer that
included a higher one would tie the rules to a mesh, the kernels to the builder, and so on. Each header included
by folder ("rules/rule_set.h") is checked against the table; an include without a folder must name a file of the
including layer. The front ends (native/cli, native/python, bench) use the public API (loopsub/) and, the CLI and the
module, the OBJ reader and writer they share (native/obj, included as "obj/obj_io.h"), which uses the core's threads
(base/): none reaches into a layer that only the core should know. The helpers the tests share with
the benchmark (tests/support, included as "support/NAME.h") are held to the public API too, so that the benchmark
reaches the core through them no more than itself. Prints one line per breach and `N passed, N failed`.

    python3 tests/lint/check_layers.py [REPOSITORY]
"""
import os
import re
import sys

# Which layers each may include besides itself and the public API (loopsub/loopsub.h).
MAY_INCLUDE = {
    "base": set(),
    "rules": {"base"},
    "topology": {"base"},
    "tables": {"base", "rules", "topology"},
    "kernels": {"base", "tables"},
    "plan": {"base", "rules", "topology", "tables", "kernels"},
    "evaluate": {"base", "tables", "kernels", "plan"},
    "tessellate": {"base", "rules", "topology", "kernels"},
    "api": {"base"},
}
# Which layers of native/src each front end (a folder of the repository) may include besides its own files and the
# public API; "support" is not a layer but the tests' shared helpers (tests/support), public API only themselves.
FRONT_ENDS = {
    "native/obj": {"base"},  # the OBJ reader and writer; the core's team of threads writes the OBJ's lines
    "native/cli": {"obj"},
    "native/python": {"obj"},  # read_obj: the command line's OBJ reader
    "bench": {"support"},
    "tests/support": {"support"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.MULTILINE)


def breaches(source_dir):
    found, checked = [], 0
    layers = sorted(name for name in os.listdir(source_dir) if os.path.isdir(os.path.join(source_dir, name)))
    for layer in layers:
        if layer not in MAY_INCLUDE:
            found.append(f"{layer}/: a folder that is no layer of docs/architecture.md")
            continue
        folder = os.path.join(source_dir, layer)
        for name in sorted(os.listdir(folder)):
            with open(os.path.join(folder, name), encoding="utf-8") as file:
                for header in INCLUDE.findall(file.read()):
                    checked += 1
                    target = header.split("/")[0] if "/" in header else layer
                    if "/" not in header and not os.path.exists(os.path.join(folder, header)):
                        found.append(f"{layer}/{name}: includes \"{header}\" without its folder")
                    elif target not in MAY_INCLUDE[layer] | {layer, "loopsub"}:
                        found.append(f"{layer}/{name}: includes \"{header}\", but {layer} may only include "
                                     f"{', '.join(sorted(MAY_INCLUDE[layer])) or 'nothing'} below it")
    return found, checked


def front_end_breaches(repository):
    found, checked = [], 0
    for front_end, allowed in FRONT_ENDS.items():
        folder = os.path.join(repository, front_end)
        for name in sorted(os.listdir(folder)):
            if not name.endswith((".h", ".cpp")):
                continue
            with open(os.path.join(folder, name), encoding="utf-8") as file:
                for header in INCLUDE.findall(file.read()):
                    checked += 1
                    if "/" not in header:
                        if not os.path.exists(os.path.join(folder, header)):
                            found.append(f"{front_end}/{name}: includes \"{header}\", no file of {front_end}")
                    elif header.split("/")[0] not in allowed | {"loopsub"}:
                        found.append(f"{front_end}/{name}: includes \"{header}\", but {front_end} may only use the "
                                     f"public API{''.join(f' and {layer}/' for layer in sorted(allowed))}")
    return found, checked


if __name__ == "__main__":
    repository = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    found, checked = breaches(os.path.join(repository, "native", "src"))
    front_found, front_checked = front_end_breaches(repository)
    found, checked = found + front_found, checked + front_checked
    for line in found:
        print(line)
    print(f"{checked - len(found)} passed, {len(found)} failed")
    sys.exit(1 if found else 0)
