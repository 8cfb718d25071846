"""The structure of a result, whichever way it is cut: by levels (PlanOutput, the core's Plan) or by the camera
(TessellationOutput, the core's Tessellation), and the one way a Source's values are refined on either (refine).
result.build_mesh reads the same things of both: the triangles, the cage triangle each lies in, the edges, the cage
edge each lies on, the crease weights the result inherits, and the refined values.
"""
import numpy as np

from .. import native
from ..native import LoopSubError
from ..blender import mesh_arrays
from ..model import geometry
from . import tags


def refine(output, source, written=None, into=None):
    """The Refined values of source on output (built from source's plan key). written: the Inputs of the result it
    updates in place; the UV maps and corner channels whose values are still those are not refined again (None in the
    Refined): the result holds them already, and playback moves only positions. into: a Destination, the new result's
    own arrays, which the core evaluates into where it can (the Refined then holds them)."""
    into = into or Destination()
    try:
        vertex, normals = output.refine_vertices(source, into)
        uvs = [None if written is not None and np.array_equal(written.uvs[layer], values)
               else output.refine_uvs(values, layer)
               for layer, (_, values) in enumerate(source.uv_layers)]
        corners = None
        if source.corners.parts:
            values = source.corners.packed()
            # The cage's custom normals are written on every update (update_mesh): in tangent space they are stored
            # relative to the result's geometry, which may have moved. Free normals (4.5+) do not change when
            # vertices move, nor does any corner value when only a UV does.
            unchanged = (written is not None and written.corners is not None
                         and np.array_equal(written.corners, values))
            corners = None if unchanged and not source.custom_normals else output.refine_corners(values)
    except LoopSubError as error:
        raise source.explain(error) from error
    return Refined(vertex, uvs, corners, normals, output.corner_normal_indices, output.triangles,
                   output.normal_per_vertex_row)


class Refined:
    """What a refinement (refine) gives for one Source: the vertex channels (N_out, C), the UV maps per output corner
    (one (T_out, 3, 2) array each), the linear corner channels (T_out, 3, C) or None, the normals in the output's
    compact form (None without the limit surface): normals (R, 3), and normal_indices, a function giving the row of
    each output corner (T_out, 3), called only for corner normals (a plan makes its indices on a first request);
    vertex_rows: whether row v is vertex v's normal (a plan's: past N_out, the sides of vertices whose fan a crease,
    corner or boundary splits; Plan.evaluate_with_limit_normals, docs/python.md), not a face point's (a
    tessellation's); and the output triangles. A UV map or the corner channels left as the result holds them (refine's
    written) are None."""

    def __init__(self, vertex, uvs, corners, normals, normal_indices, triangles, vertex_rows=True):
        self.vertex = vertex
        self.uvs = uvs
        self.corners = corners
        self.normals = normals
        self.normal_indices = normal_indices
        self.triangles = triangles
        self.vertex_rows = vertex_rows

    def corner_normals(self):
        """The limit normals per output corner, (T_out, 3, 3): a new array."""
        return geometry.take_rows(self.normals, self.normal_indices())

    def vertex_normals(self):
        """The limit normals per output vertex, (N_out, 3), when all corners of each vertex take one normal (no crease
        splits a fan: the core then gives one normal per vertex, a boundary vertex's its one side's); else None."""
        return self.normals if self.vertex_rows and len(self.normals) == len(self.vertex) else None


class Destination:
    """A new result's own arrays that a refinement evaluates into, each None where it cannot: its positions (N_out,
    3) (mesh_arrays.position_array) and its free normals per vertex (N_out, 3) (shading.free_vertex_normal_array, made
    only where the limit normals are one per vertex: normals.vertex_normal_destination). New arrays of their size would
    cost a copy, and page faults inside Blender, which reuses little of its freed memory (docs/benchmark.md)."""

    def __init__(self, positions=None, vertex_normals=None):
        self.positions = positions
        self.vertex_normals = vertex_normals

    def positions_for(self, vertex_width):
        """Where vertex channels of this width go: the positions' array when they are positions alone."""
        return self.positions if vertex_width == 3 else None


class PlanOutput:
    """Levels of refinement: the plan numbers the result's vertices, edges and triangles (docs/python.md, Output
    order), so no edge is searched for."""

    def __init__(self, plan):
        self.plan = plan
        self.triangles = plan.triangles
        self.num_vertices = plan.num_output_vertices

    @property
    def parent_triangles(self):
        # The core works them out on first use (5 MB at 1.28 million triangles): most results need none.
        return self.plan.parent_triangles

    def num_edges(self):
        return native.run(lambda: self.plan.num_output_edges)

    def write_edges(self, mesh):
        """The result's edges (E, 2), each triangle's (edge k joins its corners k and k + 1) and its corners' vertices
        into mesh, whose edges and corners are added: by the core into Blender's arrays in one pass where the version
        lets it (mesh_arrays.edge_arrays), else copied. Returns the edges."""
        arrays = mesh_arrays.edge_arrays(mesh)
        if arrays is None:
            edges, triangle_edges = native.run(self.plan.output_edges)
            mesh_arrays.write_edges(mesh, edges, triangle_edges, self.triangles)
            return edges
        edge_vertices, corner_edges, corner_vertices = arrays
        edges, _ = native.run(self.plan.output_edges, edge_vertices, corner_edges.reshape(-1, 3),
                              corner_vertices.reshape(-1, 3))
        return edges

    def edge_parents(self, edges, cage):
        """The cage edge each edge lies on, -1 inside a cage face: the core's, down its numbering."""
        return native.run(self.plan.output_edge_parents, cage.side_edges())

    def has_vertex_creases(self):
        return len(self.plan.corner_vertices) > 0

    def creases(self, cage, options, edges):
        """(edge weights (E,), vertex weights (V,)): the core's decremented sharpness (OpenSubdiv) or the carried
        weights (seed rules)."""
        plan = self.plan
        edge_weights = np.zeros(len(edges), dtype=np.float32)
        edge_weights[plan.crease_edge_indices] = geometry.child_crease_weights(plan.crease_sharpness, options.rules)
        vertex_weights = np.zeros(self.num_vertices, dtype=np.float32)
        vertex_weights[plan.corner_vertices] = geometry.child_crease_weights(plan.corner_sharpness, options.rules)
        return edge_weights, vertex_weights

    def write_tags(self, mesh, num_edges):
        tags.write_plan_tags(mesh, self.plan, num_edges)

    def one_normal_per_vertex(self):
        """Whether the limit normals are one per vertex (no crease, corner or boundary splits a fan)."""
        return self.plan.num_limit_normals == self.num_vertices

    # Limit normals in rows per vertex (and past them, per side of a split fan): Refined.vertex_normals.
    normal_per_vertex_row = True

    def refine_vertices(self, source, into):
        """(the vertex channels (N_out, C), the limit normals or None): positions first among the channels, the others
        refined with the same (limit) weights; into the Destination's arrays where it has them."""
        out = into.positions_for(source.vertex.width)
        if source.options.use_limit_surface:
            return native.run(self.plan.evaluate_with_limit_normals, source.vertex.packed(), out, into.vertex_normals)
        return native.run(self.plan.evaluate, source.vertex.packed(), out), None

    def refine_uvs(self, values, layer):
        """A UV map's values per output corner (T_out, 3, 2)."""
        return geometry.take_rows(native.run(self.plan.evaluate_face_varying, values, layer=layer),
                                  self.plan.face_varying_indices(layer))

    def refine_corners(self, values):
        """Corner channels (T, 3, C) per output corner, refined linearly per face."""
        return native.run(self.plan.evaluate_face_varying, values)

    def corner_normal_indices(self):
        # The core makes them on a first request (13 ms for 1.28 million triangles): asked for corner normals only.
        return self.plan.corner_normal_indices

    def refine_vertex_values(self, values):
        """Further vertex channels (V, C) of the cage, refined as the Refined's vertex channels are."""
        return native.run(self.plan.evaluate, values)


class TessellationOutput:
    """The limit surface cut by the rates of the cage's edges (Adaptive Subdivision): the points are the cage's
    vertices, then the points inside its edges, then those inside its triangles; each triangle's corners have their
    parameters (u, v) in the cage triangle they lie in, which place the values the core does not refine: point and
    corner attributes and vertex groups are interpolated linearly within each cage triangle. UV maps are refined by
    the core as levels refine them (UV Smooth), each as a mesh of its own cut by the same rates."""

    def __init__(self, tessellation, cage, options):
        self.tessellation = tessellation
        self.notes = tessellation.notes  # what the core's checks tell of the cage, as a Plan's notes
        self.cage = cage
        self.options = options
        self.triangles = tessellation.triangles
        self.parent_triangles = tessellation.parent_triangles
        self.num_vertices = tessellation.num_points
        # Linear values are worked out once per face point (each in one cage triangle, at its parameters), then read
        # per corner or per point: a point or a corner takes one of its face points.
        corner_face_points = tessellation.corner_face_points.ravel()
        self.face_point_parent = np.empty(tessellation.num_face_points, dtype=np.int32)
        self.face_point_parent[corner_face_points] = np.repeat(self.parent_triangles, 3)
        self.point_face_point = np.empty(self.num_vertices, dtype=np.int32)
        self.point_face_point[self.triangles.ravel()] = corner_face_points
        self._edges = self._edge_parents = None

    def _output_edges(self):
        """(edge_vertices (E, 2), triangle_edges (T, 3)), worked out once."""
        if self._edges is None:
            self._edges = native.run(self.tessellation.output_edges)
        return self._edges

    def num_edges(self):
        return len(self._output_edges()[0])

    def write_edges(self, mesh):
        """As PlanOutput.write_edges, copied."""
        edges, triangle_edges = self._output_edges()
        mesh_arrays.write_edges(mesh, edges, triangle_edges, self.triangles)
        return edges

    def edge_parents(self, edges, cage):
        """The cage edge each edge (of write_edges()) lies on, -1 inside a cage triangle."""
        if self._edge_parents is None:
            sides_of_edges = geometry.tessellated_edge_sides(self.tessellation.corner_face_points,
                                                             self.tessellation.face_point_parameters)
            self._edge_parents = geometry.tessellated_edge_parents(
                self._output_edges()[1], sides_of_edges, self.parent_triangles, cage.side_edges(), len(edges))
        return self._edge_parents

    def has_vertex_creases(self):
        return len(self.cage.tags(self.options)["corner_vertices"]) > 0

    def _per_face_point(self, corner_values):
        """Values per cage corner (T, 3, C), linear in each cage triangle, at every face point."""
        return geometry.interpolate_in_triangles(corner_values, self.face_point_parent,
                                                 self.tessellation.face_point_parameters)

    def refine_vertex_values(self, values):
        """Further vertex channels (V, C) of the cage, linear in its triangles as the Refined's are (the points'
        own)."""
        return geometry.take_rows(self._per_face_point(geometry.take_rows(values, self.cage.triangles)),
                                  self.point_face_point)

    def creases(self, cage, options, edges):
        """(edge weights (E,), vertex weights (V,)) on the limit surface (geometry.limit_crease_weights): the edges on
        a creased cage edge and the cage's corners."""
        crease_tags = cage.tags(options)
        edge_weights = np.zeros(len(edges), dtype=np.float32)
        if len(crease_tags["crease_edges"]):
            cage_weights = np.zeros(len(cage.edge_vertices), dtype=np.float32)
            tagged = geometry.lookup_edges(cage.edge_vertices, crease_tags["crease_edges"], cage.num_vertices)
            found = tagged >= 0
            cage_weights[tagged[found]] = geometry.limit_crease_weights(crease_tags["crease_sharpness"][found],
                                                                        options.rules)
            edge_weights = geometry.inherit_edge_values(cage_weights, self.edge_parents(edges, cage))
        vertex_weights = np.zeros(self.num_vertices, dtype=np.float32)
        vertex_weights[crease_tags["corner_vertices"]] = geometry.limit_crease_weights(
            crease_tags["corner_sharpness"], options.rules)
        return edge_weights, vertex_weights

    def write_tags(self, mesh, num_edges):
        """None: the tags say how refinement goes on, and the limit surface is where it ends."""

    def one_normal_per_vertex(self):
        """False: the normals are one per face point (a point on a cage edge has one in each triangle beside it)."""
        return False

    # Limit normals one per face point (a point on a cage edge has one in each triangle beside it).
    normal_per_vertex_row = False

    def refine_vertices(self, source, into):
        """(the vertex channels (N_out, C), the normals per face point): positions and normals on the limit surface,
        the other channels linear in the cage triangles; positions alone into the Destination's array. The channels
        interpolated here pass the core's checks first (native.refusal), as the positions pass them in its evaluation:
        each frame, where there are any."""
        if source.vertex.width > 3 or source.corners.parts:
            values = {"face_varying": source.corners.packed()} if source.corners.parts else {}
            problems = [item for item in source.cage.diagnose(positions=source.vertex.packed(), **values)
                        if not item.is_note]
            if problems:
                raise native.refusal(problems[0])
        points, normals = native.run(self.tessellation.evaluate, source.cage.positions,
                                     into.positions_for(source.vertex.width))
        vertex = points
        if source.vertex.width > 3:
            vertex = self.refine_vertex_values(source.vertex.packed())
            vertex[:, source.vertex.columns["position"]] = points
        return vertex, normals

    def refine_uvs(self, values, layer):
        """A UV map's values per output corner (T_out, 3, 2), refined by UV Smooth on a mesh of its own cut by the
        same rates."""
        return geometry.take_rows(native.run(self.tessellation.evaluate_face_varying, values, layer=layer),
                                  self.tessellation.corner_face_points)

    def refine_corners(self, values):
        """Corner channels (T, 3, C) per output corner, linear in each cage triangle."""
        return geometry.take_rows(self._per_face_point(values), self.tessellation.corner_face_points)

    def corner_normal_indices(self):
        return self.tessellation.corner_face_points
