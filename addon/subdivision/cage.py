"""Reading what a subdivision needs from a mesh: the cage as the core sees it (triangles, edges, crease weights),
the checks and notes an artist gets, and Source, everything one subdivision reads gathered once.
"""
from typing import NamedTuple, Optional

import bpy
import numpy as np

from .. import native
from ..blender import creases, mesh_arrays, shading
from ..blender.mesh_arrays import CREASE_TAG, VERTEX_TYPE_TAG, read_array, read_attribute
from ..model import geometry, memory
from ..native import LoopSubError


class Topology:
    """What the rules see of a mesh: its triangles, its edges with their face counts, and its crease weights."""

    def __init__(self, num_vertices, triangles, edge_vertices, edge_face_counts, edge_weights, vertex_weights):
        self.num_vertices = num_vertices
        self.triangles = triangles
        self.edge_vertices = edge_vertices
        self.edge_face_counts = edge_face_counts
        self.edge_weights = edge_weights
        self.vertex_weights = vertex_weights

    def tags(self, options):
        # Loose (wire) edges are not part of the surface: the core only takes creases on its triangles' edges. Only
        # creased edges are gathered (most of a cage's are not).
        creased = np.flatnonzero((self.edge_weights > 0) & (self.edge_face_counts > 0) if options.use_creases else ())
        vertex_weights = self.vertex_weights if options.use_creases else self.vertex_weights[:0]
        return geometry.crease_tags(self.edge_vertices[creased], self.edge_weights[creased], vertex_weights,
                                    options.rules, options.crease_threshold)

    def plan(self, options, levels, cones, face_varying_indices=()):
        return native.build_plan(self.triangles, self.num_vertices, levels, options, self.tags(options), cones,
                                 face_varying_indices)


class Cage(Topology):
    """The control mesh as the core sees it: Blender's triangulation of its faces, and its crease weights."""

    def __init__(self, mesh):
        num_vertices = len(mesh.vertices)
        self.positions = mesh_arrays.read_positions(mesh)
        self.num_polygons = len(mesh.polygons)
        self.num_loops = len(mesh.loops)
        loop_vertices, loop_edges = mesh_arrays.read_corners(mesh)
        self.triangle_loops, self.triangle_polygons, triangles = mesh_arrays.read_loop_triangles(mesh, loop_vertices)
        # A face of n corners is n - 2 of Blender's triangles: those not of three corners are those not of one
        # triangle, found without reading MeshPolygon.loop_total a face at a time.
        self.num_triangulated = int(np.count_nonzero(
            np.bincount(self.triangle_polygons, minlength=self.num_polygons) != 1))
        self.loop_edges = loop_edges
        self._side_edges = None
        super().__init__(num_vertices,
                         triangles,
                         mesh_arrays.read_edge_vertices(mesh),
                         geometry.edge_face_counts(loop_edges, len(mesh.edges)),
                         creases.read_edge_creases(mesh),
                         creases.read_vertex_creases(mesh))

    def side_edges(self):
        """The mesh edge of each side of each triangle, -1 for diagonals (geometry.side_edges), worked out once."""
        if self._side_edges is None:
            self._side_edges = geometry.side_edges(self.triangles, self.triangle_loops, self.loop_edges,
                                                   self.edge_vertices)
        return self._side_edges

    def validate(self, name, topology=True):
        """The checks that give a clearer message here than the core's own; topology=False skips those that depend on
        the triangles alone (for triangles already checked)."""
        if not len(self.triangles):
            raise LoopSubError(f"{name} has no faces to subdivide")
        finite(self.positions, name, "the position", "vertex", "vertices")
        if not topology:
            return
        degenerate = geometry.degenerate_triangles(self.triangles)
        if len(degenerate):
            face = self.triangle_polygons[degenerate[0]]
            raise LoopSubError(f"{name}: face {face} repeats a vertex "
                               f"({counted(len(degenerate), 'degenerate triangle')}); "
                               "Mesh ▸ Clean Up ▸ Degenerate Dissolve can fix it")


def finite(values, name, what, element, elements):
    """values, rows of one element each (a vertex, a corner), where all are finite numbers; else a LoopSubError that
    names the first element that is not, as the artist finds it (the Spreadsheet's index): "Hero: UV map "UVMap" has
    a non-finite value at corner 37 (1 such corner)". The core would refuse it too, but by its own numbering."""
    if np.isfinite(values).all():  # at once: numpy's all along rows of three is many times slower
        return values
    bad = np.flatnonzero(~np.isfinite(values.reshape(len(values), -1)).all(axis=1))
    raise LoopSubError(f"{name}: {what} has a non-finite value at {element} {bad[0]} "
                       f"({counted(len(bad), 'such ' + element, 'such ' + elements)})")


def counted(count, singular, plural=None):
    """A count and its noun, singular for one ("1 vertex", "2 vertices"); plural defaults to singular + "s"."""
    return f"{count} {singular if count == 1 else (plural or singular + 's')}"


def read_vertex_groups(mesh, num_groups):
    """(V, G) weights (G may be 0). Blender has no bulk accessor for deform weights (they are per-vertex lists), so
    this is the one place that walks the cage's vertices in Python; it runs on the cage, never on the 4^L larger
    result."""
    weights = np.zeros((len(mesh.vertices), num_groups), dtype=np.float32)
    if not num_groups:
        return weights
    for vertex in mesh.vertices:
        for element in vertex.groups:
            if element.group < num_groups:
                weights[vertex.index, element.group] = element.weight
    return weights


def cone_group_index(obj, options):
    """Index of the cone vertex group, or None when the rules or settings use no cones."""
    if options.rules != 'HOPPE94' or not options.cone_group:
        return None
    group = obj.vertex_groups.get(options.cone_group)
    if group is None:
        raise LoopSubError(f"{obj.name}: cone vertex group \"{options.cone_group}\" does not exist")
    return group.index


def cone_vertices(group_weights, cone_index):
    if cone_index is None:
        return np.zeros(0, dtype=np.int32)
    return np.flatnonzero(group_weights[:, cone_index] > 0).astype(np.int32)


def check_object(obj):
    if obj.type != 'MESH':
        raise LoopSubError(f"{obj.name} is not a mesh")
    mesh = obj.data
    if mesh.users > 1:
        raise LoopSubError(f"{obj.name}: cannot apply to multi-user mesh data \"{mesh.name}\"")
    if mesh.shape_keys is not None:
        raise LoopSubError(f"{obj.name}: cannot apply to a mesh with shape keys")
    if mesh.is_editmode:
        raise LoopSubError(f"{obj.name} is in Edit Mode")


def check_memory(source):
    """Raises LoopSubError, saying what it would need and what is free, where subdividing the source's mesh with its
    options would need more memory than this process may still use (memory.py: the peak of the whole update, the
    core's plan, the result in Blender and its copies; the memory free, or left in the cgroup Blender runs in). A
    request past it would otherwise get Blender killed for lack of memory, unsaved work lost."""
    mesh, options = source.mesh, source.options
    triangles = len(mesh.loops) - 2 * len(mesh.polygons)
    edges = len(mesh.edges) + triangles - len(mesh.polygons)
    contents = source.contents()
    required = memory.estimate_bytes(
        len(mesh.vertices), edges, triangles, options.levels,
        native.estimate_plan_bytes(len(mesh.vertices), edges, triangles, options.levels, contents["vertex_channels"]),
        limit_surface=options.use_limit_surface, version=bpy.app.version, drawn=not bpy.app.background, **contents)
    available = memory.available_bytes()
    if not memory.fits(required, available):
        raise LoopSubError(memory.describe(required, available, f"Level {options.levels}"))


class _Channels:
    """Several arrays packed side by side along their last axis for one native call, unpacked by key afterwards."""

    def __init__(self):
        self.parts = []
        self.columns = {}
        self.width = 0

    def add(self, key, values):
        self.columns[key] = slice(self.width, self.width + values.shape[-1])
        self.width += values.shape[-1]
        self.parts.append(values)

    def packed(self):
        return np.ascontiguousarray(np.concatenate(self.parts, axis=-1), dtype=np.float32)


def _notes(name, cage):
    """What an artist should be told about a cage that subdivides."""
    notes = []
    if cage.num_triangulated:
        notes.append(('INFO', f"{name}: triangulated {counted(cage.num_triangulated, 'non-triangle face')} "
                              "with Blender's tessellation first"))
    loose_edges = int(np.count_nonzero(cage.edge_face_counts == 0))
    if loose_edges:
        notes.append(('WARNING', f"{name}: {counted(loose_edges, 'loose edge')} (in no face) "
                                 f"{'is' if loose_edges == 1 else 'are'} not carried over"))
    duplicates = geometry.duplicate_triangles(cage.triangles)
    if len(duplicates):
        first, second = cage.triangle_polygons[duplicates[0]]
        notes.append(('WARNING', f"{name}: faces {first} and {second} lie on the same three vertices "
                                 f"({counted(len(duplicates), 'such pair')}); their edges are non-manifold and "
                                 "stay sharp, as in Subdivision Surface"))
    flipped = geometry.edges_run_the_same_way(cage.triangles)
    if flipped:
        notes.append(('WARNING', f"{name}: {counted(flipped, 'edge')} {'joins' if flipped == 1 else 'join'} faces "
                                 "that face opposite ways and stay sharp (Mesh ▸ Normals ▸ Recalculate Outside "
                                 "turns them)"))
    cracks = geometry.shared_positions(cage.positions)
    if cracks:
        notes.append(('WARNING', f"{name}: {counted(cracks, 'vertex', 'vertices')} "
                                 f"{'shares' if cracks == 1 else 'share'} a position with another; the cracks "
                                 "stay open (Merge by Distance welds them)"))
    return notes


def _normal_notes(name, mesh, source):
    """What an artist should be told about the result's normals."""
    notes = []
    if source.custom_normals and source.options.use_limit_surface:
        notes.append(('INFO', f"{name}: its custom split normals are carried over (interpolated per face) in place "
                              "of the limit normals"))
    elif mesh.has_custom_normals and not source.custom_normals:
        notes.append(('WARNING', f"{name}: its custom split normals are not carried over (Auto Smooth is off, so "
                                 "they do not shade it)"))
    return notes


class Source:
    """Everything a subdivision reads from one input mesh, gathered once: the cage and its tags, the vertex channels
    (positions, point attributes, vertex-group weights) packed for the core, the UV maps as face-varying layers (each
    welded per vertex: corners of a vertex with equal UVs share a value), the linear corner channels (corner
    attributes, custom split normals), and the per-face and per-edge data that the result inherits.

    obj gives the vertex-group names and the cone group; mesh is its own data (apply) or its evaluated mesh up to the
    Loop Subdivision entry (the live entry). checked_triangles: triangles validated before (the live entry's last
    ones): when the cage has the same, the checks and notes that depend on the topology alone are skipped, and so
    are the notes (messages) altogether, since the result is then only updated."""

    def __init__(self, obj, mesh, options, checked_triangles=None):
        self.mesh = mesh
        self.options = options
        self.cage = cage = Cage(mesh)
        known = checked_triangles is not None and np.array_equal(cage.triangles, checked_triangles)
        cage.validate(obj.name, topology=not known)
        self.messages = [] if known else _notes(obj.name, cage)
        self.group_names = [group.name for group in obj.vertex_groups]
        self.group_weights = read_vertex_groups(mesh, len(self.group_names))
        self.cone_index = cone_group_index(obj, options)
        self.cones = cone_vertices(self.group_weights, self.cone_index)

        # Handled on their own: positions, tags (recomputed), per-face material and shading, sharp edges, creases, UVs,
        # and (4.5+) seams and custom normals.
        skip = ({CREASE_TAG, VERTEX_TYPE_TAG, "position", "material_index", "sharp_face", "sharp_edge"}
                | creases.crease_attribute_names() | mesh_arrays.seam_and_normal_attribute_names()
                | {uv.name for uv in mesh.uv_layers})
        self.point, self.corner, self.face, self.edge, dropped = geometry.plan_attributes(
            [(a.name, a.domain, a.data_type) for a in mesh.attributes], skip)
        if dropped:
            self.messages.append(('WARNING', f"{obj.name}: attributes not carried over: "
                                        + ", ".join(f"{n} ({d.lower()} {t.lower()})" for n, d, t in dropped)))

        # Vertex channels: positions and point attributes refine together with the same weights, on every update.
        # Vertex groups refine with those weights too, but only when a result is built (result._write_vertex_groups):
        # an update in place leaves them as they are, and a rig's hundreds of groups would multiply its work.
        self.vertex = _Channels()
        self.vertex.add("position", cage.positions)
        for name, _, _ in self.point:
            self.vertex.add(("attribute", name), finite(read_attribute(mesh.attributes[name], cage.num_vertices),
                                                        obj.name, f'attribute "{name}"', "vertex", "vertices"))

        # Edge data passes to the child edges on each cage edge: seam and sharp marks, edge attributes.
        self.edge_flags = mesh_arrays.read_edge_flags(mesh)
        self.edge_values = [read_attribute(mesh.attributes[name], len(mesh.edges)) for name, _, _ in self.edge]

        # UV maps: face-varying layers with their own topology (a seam splits the value, not the vertex), refined as
        # UV Smooth says, to the limit with the limit surface.
        self.uv_names = [uv.name for uv in mesh.uv_layers]
        self.uv_layers = [native.weld_corner_values(cage.triangles, cage.num_vertices,
                                                    finite(read_array(uv.data, "uv", cage.num_loops, 2, np.float32),
                                                           obj.name, f'UV map "{uv.name}"', "corner", "corners")
                                                    [cage.triangle_loops])
                          for uv in mesh.uv_layers]

        # Corner channels refined linearly per face: corner attributes, and custom split normals where the mesh
        # shades with them (they then take the place of the limit normals).
        self.corners = _Channels()
        for name, _, _ in self.corner:
            self.corners.add(("attribute", name),
                             finite(read_attribute(mesh.attributes[name], cage.num_loops), obj.name,
                                    f'attribute "{name}"', "corner", "corners")[cage.triangle_loops])
        self.custom_normals = shading.custom_normals_in_use(mesh)
        if self.custom_normals:
            self.corners.add("normal", shading.read_corner_normals(mesh)[cage.triangle_loops])
        # The result shades with the limit normals as custom normals, on smooth faces (normals.write_limit_normals).
        self.limit_normals = options.use_limit_surface and not self.custom_normals
        self.blender_corners = None  # result corners that keep Blender's own normal (build_mesh sets it)

        self.materials, self.smooth = mesh_arrays.read_face_materials_and_smooth(mesh)
        self.face_values = [read_attribute(mesh.attributes[name], cage.num_polygons) for name, _, _ in self.face]
        if not known:
            self.messages += _normal_notes(obj.name, mesh, self)

    def contents(self):
        """What besides its counts sizes a result (memory.estimate_output_bytes' arguments): floats per vertex and per
        corner refined on every update, UV maps, vertex groups and their weights above zero per cage vertex."""
        return dict(vertex_channels=self.vertex.width, corner_channels=self.corners.width,
                    uv_layers=len(self.uv_layers), groups=len(self.group_names),
                    group_weights=np.count_nonzero(self.group_weights) / max(1, self.cage.num_vertices))

    def plan_key(self):
        """What the plan depends on: equal keys, equal plans."""
        return (self.options, self.cage.triangles, *self.cage.tags(self.options).values(), self.cones,
                *(indices for indices, _ in self.uv_layers))

    def layout_key(self):
        """What, besides the plan, fixes the result's structure and its non-interpolated data: while it and the plan
        stay the same, a result can be updated in place (update_mesh) instead of built anew."""
        return (tuple(self.point), tuple(self.corner), tuple(self.face), tuple(self.uv_names), self.custom_normals,
                self.limit_normals,
                tuple(self.edge), tuple(self.group_names), self.group_weights, self.materials, self.smooth,
                *self.face_values, *self.edge_values, *self.edge_flags.values(), self.cage.edge_weights,
                self.cage.vertex_weights)

    def plan(self, levels=None):
        return self.cage.plan(self.options, self.options.levels if levels is None else levels, self.cones,
                              [indices for indices, _ in self.uv_layers])

    def inputs(self):
        """The values a refinement reads (for the live entry: equal inputs on the same plan, equal result)."""
        return Inputs(self.vertex.packed(), self.corners.packed() if self.corners.parts else None,
                      tuple(values for _, values in self.uv_layers))


class Inputs(NamedTuple):
    """The values one refinement reads, by name: the vertex channels (V, C), the corner channels (T, 3, C) or None,
    and each UV map's welded values."""
    vertex: np.ndarray
    corners: Optional[np.ndarray]
    uvs: tuple

    def equals(self, other):
        return (other is not None and np.array_equal(self.vertex, other.vertex)
                and _same(self.corners, other.corners) and len(self.uvs) == len(other.uvs)
                and all(np.array_equal(a, b) for a, b in zip(self.uvs, other.uvs)))


def _same(a, b):
    return a is None and b is None or a is not None and b is not None and np.array_equal(a, b)
