"""How much memory an update of a Loop Subdivision entry needs, and how much this process may still use, so that too
many levels give a report instead of getting Blender killed for lack of memory.

No bpy here: the tests load this file with plain Python.
"""
import ctypes
import os
import sys

# --- What this process may still use ----------------------------------------------------------------------------------

# cgroup v1 writes "no limit" as the largest page-aligned signed 64-bit number (9223372036854771712); anything this
# large is no limit either.
_NO_V1_LIMIT = 1 << 62


def available_bytes(root="/"):
    """Bytes this process may still use: the least of what the system has available and what every memory cgroup it
    runs in still allows. None when no source can be read; the caller then checks nothing. root: where /proc and /sys
    are (tests point it at a fake tree)."""
    found = [value for value in (meminfo_available(root), cgroup_v2_available(root), cgroup_v1_available(root),
                                 windows_available(), sysconf_available())
             if value is not None]
    return max(0, min(found)) if found else None


def meminfo_available(root="/"):
    """Linux's own estimate of what can be allocated without swapping: free memory plus reclaimable caches."""
    try:
        return _field(_read(root, "proc/meminfo"), "MemAvailable:") * 1024
    except (OSError, ValueError, TypeError):
        return None


def cgroup_v2_available(root="/"):
    """What the cgroup v2 hierarchy still allows: memory.max minus memory.current, plus the inactive page cache, which
    the kernel reclaims before it kills. Every ancestor counts, since a parent's limit may be the tighter one."""
    path = _cgroup_path(root, lambda hierarchy, controllers: hierarchy == "0" and controllers == "")
    if path is None:
        return None
    found = []
    for directory in _ancestors("sys/fs/cgroup", path):
        try:
            limit = _read(root, directory + "/memory.max").strip()
            if limit == "max":
                continue
            free = int(limit) - int(_read(root, directory + "/memory.current"))
            found.append(free + _field(_read(root, directory + "/memory.stat"), "inactive_file"))
        except (OSError, ValueError, TypeError):
            continue  # not this level (a container shows only part of the host's path): its parents still count
    return min(found) if found else None


def cgroup_v1_available(root="/"):
    """What the cgroup v1 memory controller still allows: memory.limit_in_bytes minus memory.usage_in_bytes, plus
    the inactive page cache (total_: of the cgroup and those below it, as usage counts them), at every ancestor."""
    path = _cgroup_path(root, lambda hierarchy, controllers: "memory" in controllers.split(","))
    if path is None:
        return None
    found = []
    for directory in _ancestors("sys/fs/cgroup/memory", path):
        try:
            limit = int(_read(root, directory + "/memory.limit_in_bytes"))
            if limit >= _NO_V1_LIMIT:
                continue
            free = limit - int(_read(root, directory + "/memory.usage_in_bytes"))
            found.append(free + _field(_read(root, directory + "/memory.stat"), "total_inactive_file"))
        except (OSError, ValueError, TypeError):
            continue
    return min(found) if found else None


class _MemoryStatusEx(ctypes.Structure):
    _fields_ = [("dwLength", ctypes.c_uint32), ("dwMemoryLoad", ctypes.c_uint32),
                ("ullTotalPhys", ctypes.c_uint64), ("ullAvailPhys", ctypes.c_uint64),
                ("ullTotalPageFile", ctypes.c_uint64), ("ullAvailPageFile", ctypes.c_uint64),
                ("ullTotalVirtual", ctypes.c_uint64), ("ullAvailVirtual", ctypes.c_uint64),
                ("ullAvailExtendedVirtual", ctypes.c_uint64)]


def windows_available():
    """Windows: the physical memory available (GlobalMemoryStatusEx)."""
    if sys.platform != "win32":
        return None
    status = _MemoryStatusEx()
    status.dwLength = ctypes.sizeof(status)
    if not ctypes.windll.kernel32.GlobalMemoryStatusEx(ctypes.byref(status)):
        return None
    return int(status.ullAvailPhys)


def sysconf_available():
    """Other systems, as far as sysconf tells: the free pages where it counts them (BSDs); on macOS, which counts
    none, the physical memory, since past it macOS swaps and compresses until the system stalls. Linux and Windows have
    better sources above (sysconf's free pages on Linux leave out the reclaimable caches)."""
    if sys.platform.startswith(("linux", "win")):
        return None
    for name in ("SC_AVPHYS_PAGES", "SC_PHYS_PAGES"):
        try:
            return os.sysconf(name) * os.sysconf("SC_PAGE_SIZE")
        except (ValueError, OSError, AttributeError):
            continue
    return None


def _read(root, path):
    # Cgroup paths are bytes (a unit may be named in any script): surrogateescape keeps them as the files are named.
    with open(os.path.join(root, path), encoding="utf-8", errors="surrogateescape") as file:
        return file.read()


def _field(text, key):
    """The number after key in a "key value" listing (/proc/meminfo, memory.stat)."""
    for line in text.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0] == key:
            return int(parts[1])
    return None


def _cgroup_path(root, matches):
    """The path of the process's cgroup in the hierarchy that matches(hierarchy id, controllers) picks, from
    /proc/self/cgroup's "id:controllers:/path" lines."""
    try:
        lines = _read(root, "proc/self/cgroup").splitlines()
    except OSError:
        return None
    for line in lines:
        hierarchy, _, rest = line.partition(":")
        controllers, _, path = rest.partition(":")
        if path.startswith("/") and matches(hierarchy, controllers):
            return path
    return None


def _ancestors(mount, path):
    """The cgroup's directory and each parent's up to the hierarchy's root, relative to root."""
    parts = [part for part in path.split("/") if part]
    return ["/".join([mount] + parts[:count]) for count in range(len(parts), -1, -1)]


# --- What an update needs ---------------------------------------------------------------------------------------------

def output_counts(vertices, edges, triangles, levels):
    """(vertices, edges, triangles) after levels levels: each level adds a vertex per edge, splits each edge in two and
    adds three edges and four triangles per triangle."""
    for _ in range(levels):
        vertices, edges, triangles = vertices + edges, 2 * edges + 3 * triangles, 4 * triangles
    return vertices, edges, triangles


class _Bytes:
    """Bytes per output vertex, edge, corner and triangle (three corners a triangle), and per corner of each UV map."""

    def __init__(self, vertex=0, edge=0, corner=0, triangle=0, uv=0):
        self.vertex, self.edge, self.corner, self.triangle, self.uv = vertex, edge, corner, triangle, uv

    def __add__(self, other):
        return _Bytes(self.vertex + other.vertex, self.edge + other.edge, self.corner + other.corner,
                      self.triangle + other.triangle, self.uv + other.uv)

    def of(self, counts, uv_layers=0):
        vertices, edges, triangles = counts
        return (self.vertex * vertices + self.edge * edges + (self.corner + self.uv * uv_layers) * 3 * triangles
                + self.triangle * triangles)


_NONE = _Bytes()

# The constants are the layouts of the arrays named, then raised until the estimate covered the peak RSS growth measured
# on adding an entry (then writing its limit normals, an evaluation and an edit) to a UV-mapped 20,480-triangle
# icosphere and a triangulated 100 x 100 grid at levels 1-5, limit surface on and off, in Blender 3.4.1 (background and
# its interface under Xvfb) and the bpy 4.5.15 module (background). Blender 3.5-4.4 and 5.x use 4.5's constants, and
# everything after 3.4 uses the draw cache measured in 3.4's interface (the wheels have none). The estimate is 1.02-1.36
# times the measured peak at levels 3-5 (docs/benchmark.md), e.g. (MiB):
#
#   Blender 3.4.1, icosphere level 5, limit on / off:   measured 15,384 / 8,230    estimated 17,394 / 8,634
#   Blender 3.4.1, interface, level 4, limit on / off:  measured 4,333 / 3,044     estimated 5,573 / 3,458
#   bpy 4.5.15, icosphere level 5, limit on / off:      measured 15,075 / 4,822    estimated 16,884 / 5,104

# (a) The core's plan beyond its own estimate (plan_bytes): each UV map's output indices, with the limit surface its
# limit stencils.
_CORE_UV = _Bytes(uv=4)
_CORE_UV_LIMIT = _Bytes(uv=10)

# (b) The add-on's numpy arrays. Held through the update: the refined values (4 bytes a channel of a vertex or
# corner; UV maps, with the copy of their indices that places them), with the limit surface the normals (per corner
# when calibrated; now one per vertex and side, with a per-corner copy where a side or a flat face needs one).
# Temporaries, at two moments: laying out the result's edges (Plan.output_edges), before the mesh exists; with the
# limit surface, when calibrated, finding where the limit normals split (for the viewport's sharp edges, a step the
# add-on no longer takes: every update writes the limit normals themselves). The constants stay the calibrated ones,
# on the safe side, until the limit-surface rows are measured again.
_REFINED = _Bytes(uv=12)
_LIMIT_NORMALS = _Bytes(corner=12)
_LAYOUT = _Bytes(corner=40)
_SPLIT = _Bytes(corner=185)

# (c) Blender's result mesh: what the add-on stores, and the caches Blender adds to evaluate and draw it (vertex, face
# and corner normals, the triangulation). 3.5 on, generic attributes: position, loop_vertex_type; edge vertices,
# loop_crease, sharp_edge; corner vertex and edge; face offsets, sharp_face; 8 per UV corner. 3.4: MVert, MEdge,
# MLoop, MPoly, MLoopUV (12 per UV corner). The limit surface adds custom normals (short2), which 3.4 keeps with its
# corner normals; writing them in tangent space (up to 4.4, and where marked sharp edges keep Blender's normals) holds
# Blender's normal spaces for a moment; free normals (4.5+) are a float vector a corner or a vertex.
_STORED = _Bytes(vertex=16, edge=10, corner=8, triangle=5, uv=8)
_CACHES = _Bytes(vertex=12, corner=12, triangle=28)
_WRITE_NORMALS = _Bytes(corner=45)
_STORED_3_4 = _Bytes(vertex=20, edge=13, corner=8, triangle=12, uv=12)
_CACHES_3_4 = _Bytes(vertex=12, triangle=28)
_WRITE_NORMALS_3_4 = _Bytes(corner=95)
_CUSTOM_NORMALS = _Bytes(corner=4)
_CACHES_LIMIT_3_4 = _Bytes(corner=12)

# (d) Copies of the result's arrays in evaluated meshes (Blender computes the caches once, on the mesh it draws): in
# 3.4 both the Object Info node and the Geometry Nodes modifier's output copy them (the measured growth is three
# results); from 3.5 the evaluated mesh shares the helper's arrays.
_COPIES_3_4 = 2

# (e) The viewport's draw cache: positions and normals per corner, index buffers of the triangles and edges, the
# active UV map; Blender's buffers and the driver's copy live side by side while they are uploaded.
_DRAW = _Bytes(corner=2 * 24, triangle=2 * 12, edge=2 * 8)
_DRAW_UV = _Bytes(corner=2 * 8)

# (f) Vertex groups. Blender keeps a vertex's weights above zero in an array of its own (a weight 8 bytes, the array 16
# bytes of the vertex's record and 16 of the allocator's); a result vertex takes weights from the cage vertices around
# its cage triangle, twelve where they are regular, so it has up to about _GROUP_SPREAD times a cage vertex's weights
# above zero. The weights are refined GROUP_BATCH groups at a time (result._write_vertex_groups), each batch held while
# its groups are written through a float attribute of their own.
GROUP_BATCH = 4
_GROUP_SPREAD = 12
_GROUP_VERTEX = 32
_GROUP_WEIGHT = 8

# What does not grow with the result, measured at level 1: the native module, the helper and node group, the
# allocator's arenas; with a viewport, the shaders and batches of its first drawing.
_FIXED = 48 << 20
_FIXED_DRAWN = 64 << 20


def estimate_bytes(vertices, edges, triangles, levels, plan_bytes, **arguments):
    """Peak bytes one update of an entry adds at `levels`, from the cage's counts (edges and triangles after
    triangulation: the mesh's edges plus its triangles minus its faces) and the core's own estimate of its plan and
    one evaluation of the vertex channels (plan_bytes: _loopsub.estimate_plan_bytes); arguments: as
    estimate_output_bytes."""
    return estimate_output_bytes(output_counts(vertices, edges, triangles, levels), plan_bytes, **arguments)


def estimate_output_bytes(counts, plan_bytes, uv_layers=0, corner_channels=0, vertex_channels=3, groups=0,
                          group_weights=0.0, limit_surface=True, version=(4, 5, 0), drawn=True):
    """Peak bytes one update of an entry adds for a result of counts (vertices, edges, triangles): levels' (see
    estimate_bytes) or a tessellation's; plan_bytes: the core's own. corner_channels: floats per corner refined
    linearly (colour attributes, the cage's own custom normals); vertex_channels: floats per vertex (3 for positions,
    plus point attributes); groups: vertex groups, with group_weights weights above zero per cage vertex; drawn: False
    in background mode, which has no viewport.

    The peak comes either while the update builds the result (the refined values, then the larger of two moments'
    temporaries), or once it is shown (the result with its caches and evaluated copies, the draw cache) and, with the
    limit surface, its limit normals are written into it; the core's plan lives throughout."""
    old = version < (3, 5, 0)
    # Point attributes beyond the positions, and corner attributes, are stored too (4 bytes a channel).
    stored = (_STORED_3_4 if old else _STORED) + _Bytes(vertex=4 * (vertex_channels - 3), corner=4 * corner_channels)
    caches = _CACHES_3_4 if old else _CACHES
    refined = _REFINED + _Bytes(vertex=4 * vertex_channels, corner=4 * corner_channels)
    if groups:
        weights = min(groups, _GROUP_SPREAD * group_weights)
        stored += _Bytes(vertex=round(_GROUP_VERTEX + _GROUP_WEIGHT * weights))
        refined += _Bytes(vertex=4 * (min(groups, GROUP_BATCH) + 1))  # a batch, and the attribute written from it
    core_uv, held, split, write_normals = _CORE_UV, _NONE, _NONE, _NONE
    if limit_surface:
        core_uv += _CORE_UV_LIMIT
        stored += _CUSTOM_NORMALS
        caches += _CACHES_LIMIT_3_4 if old else _NONE
        refined += _LIMIT_NORMALS
        held, split = _LIMIT_NORMALS, _SPLIT
        write_normals = _WRITE_NORMALS_3_4 if old else _WRITE_NORMALS

    core = plan_bytes + core_uv.of(counts, uv_layers)
    build = refined.of(counts, uv_layers) + max(_LAYOUT.of(counts), (stored + split).of(counts, uv_layers))
    shown = (held + caches).of(counts) + stored.of(counts, uv_layers) * (1 + (_COPIES_3_4 if old else 0))
    fixed = _FIXED
    if drawn:
        shown += (_DRAW + (_DRAW_UV if uv_layers else _NONE)).of(counts)
        fixed += _FIXED_DRAWN
    return fixed + core + max(build, shown + write_normals.of(counts))


# The core's tessellation per output triangle, where each cage triangle is a patch of the cage (its arrays: corners'
# points and face points, parents, per face point its parameters and normal, the points): 72 bytes, measured as the
# peak growth of building and evaluating a 702,631-triangle ground plane. Triangles that are no patch go through plans
# (478 bytes a triangle measured on Suzanne): the core counts those itself, in one budget with the result and each UV
# map's cut, against the limit it is given (Tessellation.estimated_bytes; adaptive.MemoryBudget).
TESSELLATION_BYTES_PER_TRIANGLE = 72


# --- Whether it fits, and what to tell the artist ---------------------------------------------------------------------

_RESERVE_SHARE = 0.10
_RESERVE_FIXED = 256 << 20


def reserve_bytes(available):
    """What stays unused: 10% of what is free covers what the estimate leaves out (attributes of types not
    measured, fragmentation, other programs and Blender's own growth during a long update); 256 MB covers Blender's
    fixed costs around an update (an undo step, the interface) where 10% of little is less."""
    return int(_RESERVE_SHARE * available) + _RESERVE_FIXED


def fits(required, available, reserve=None):
    """Whether an update needing required bytes may run: available is None when it is unknown, which lets it run."""
    if available is None:
        return True
    return required <= available - (reserve_bytes(available) if reserve is None else reserve)


def describe(required, available, subject):
    """The report of a refused subdivision: "Level 4 needs about 31 GB; 9.2 GB are free" (subject "Level 4"). A need
    below the free memory, refused for the reserve, says so. Two amounts that would read the same get a decimal more
    until they differ ("needs about 21.3 GB; 21.1 GB are free", not "21 GB; 21 GB")."""
    need, free = format_bytes(required), format_bytes(available)
    for decimals in range(1, 4):
        if need != free or required == available:
            break
        need, free = format_bytes(required, decimals), format_bytes(available, decimals)
    text = f"{subject} needs about {need}; {free} are free"
    if required <= available:
        text += f", less {format_bytes(reserve_bytes(available))} kept for Blender and the system"
    return text


def format_bytes(count, decimals=0):
    """MB under 1000 MB, else GB (of 2^30 bytes, as systems count memory) with one decimal under 10; decimals more
    where two amounts must read apart."""
    megabytes = count / (1 << 20)
    if round(megabytes) < 1000:
        return f"{round(megabytes, decimals or None)} MB"
    gigabytes = count / (1 << 30)
    return f"{round(gigabytes, (0 if gigabytes >= 9.95 else 1) + decimals):g} GB"
