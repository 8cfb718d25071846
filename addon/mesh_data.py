"""Moving mesh data between Blender and the core: numpy arrays through foreach_get / foreach_set.

Apply builds the subdivided mesh completely in a new data-block and only then swaps it in, so any error leaves the
object's mesh untouched.
"""
import dataclasses

import bpy
import numpy as np

from . import compat, geometry, memory, native
from .native import LoopSubError

CREASE_TAG = "loop_crease"
VERTEX_TYPE_TAG = "loop_vertex_type"
# Temporary name of a float point attribute on its way to becoming a vertex group.
_GROUP_TRANSFER = "loop_subdivision_group_transfer"


def _get(collection, prop, count, width, dtype):
    values = np.empty(count * width, dtype=dtype)
    collection.foreach_get(prop, values)
    return values.reshape(count, width) if width > 1 else values


def _get_attribute(attribute, count):
    prop, width, dtype = geometry.ATTRIBUTE_LAYOUT[attribute.data_type]
    return _get(attribute.data, prop, count, width, dtype).reshape(count, width)


def _fill(attribute, data_type, values):
    attribute.data.foreach_set(geometry.ATTRIBUTE_LAYOUT[data_type][0], np.ascontiguousarray(values).ravel())


def _set_attribute(mesh, name, domain, data_type, values):
    attribute = mesh.attributes.new(name, data_type, domain)
    _fill(attribute, data_type, values)
    return attribute


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
        # Loose (wire) edges are not part of the surface: the core only takes creases on its triangles' edges.
        in_faces = self.edge_face_counts > 0 if options.use_creases else np.zeros(len(self.edge_vertices), bool)
        vertex_weights = self.vertex_weights if options.use_creases else self.vertex_weights[:0]
        return geometry.crease_tags(self.edge_vertices[in_faces], self.edge_weights[in_faces], vertex_weights,
                                    options.rules, options.crease_threshold)

    def plan(self, options, levels, cones, face_varying_indices=()):
        return native.build_plan(self.triangles, self.num_vertices, levels, options, self.tags(options), cones,
                                 face_varying_indices)


def _classifying(options):
    """Options for a plan that only classifies vertices: the limit surface plays no part in it."""
    return dataclasses.replace(options, use_limit_surface=False)


class Cage(Topology):
    """The control mesh as the core sees it: Blender's triangulation of its faces, and its crease weights."""

    def __init__(self, mesh):
        num_vertices = len(mesh.vertices)
        self.positions = _get(mesh.vertices, "co", num_vertices, 3, np.float32)
        mesh.calc_loop_triangles()
        num_triangles = len(mesh.loop_triangles)
        self.triangle_loops = _get(mesh.loop_triangles, "loops", num_triangles, 3, np.int32)
        self.triangle_polygons = _get(mesh.loop_triangles, "polygon_index", num_triangles, 1, np.int32)
        self.num_polygons = len(mesh.polygons)
        self.num_loops = len(mesh.loops)
        loop_totals = _get(mesh.polygons, "loop_total", self.num_polygons, 1, np.int32)
        self.num_triangulated = int(np.count_nonzero(loop_totals != 3))
        loop_edges = _get(mesh.loops, "edge_index", self.num_loops, 1, np.int32)
        super().__init__(num_vertices,
                         _get(mesh.loop_triangles, "vertices", num_triangles, 3, np.int32),
                         _get(mesh.edges, "vertices", len(mesh.edges), 2, np.int32),
                         geometry.edge_face_counts(loop_edges, len(mesh.edges)),
                         compat.read_edge_creases(mesh),
                         compat.read_vertex_creases(mesh))

    def validate(self, name, topology=True):
        """The checks that give a clearer message here than the core's own; topology=False skips those that depend on
        the triangles alone (for triangles already checked)."""
        if not len(self.triangles):
            raise LoopSubError(f"{name} has no faces to subdivide")
        bad = np.flatnonzero(~np.isfinite(self.positions).all(axis=1))
        if len(bad):
            raise LoopSubError(f"{name}: vertex {bad[0]} has a non-finite coordinate "
                               f"({counted(len(bad), 'such vertex', 'such vertices')})")
        if not topology:
            return
        degenerate = geometry.degenerate_triangles(self.triangles)
        if len(degenerate):
            face = self.triangle_polygons[degenerate[0]]
            raise LoopSubError(f"{name}: face {face} repeats a vertex "
                               f"({counted(len(degenerate), 'degenerate triangle')}); "
                               "Mesh ▸ Clean Up ▸ Degenerate Dissolve can fix it")


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


def check_memory(mesh, options):
    """Raises LoopSubError, saying what it would need and what is free, where subdividing mesh (the input) with
    options would need more memory than this process may still use (memory.py: the peak of the whole update, the
    core's plan, the result in Blender and its copies; the memory free, or left in the cgroup Blender runs in). A
    request past it would otherwise get Blender killed for lack of memory, unsaved work lost."""
    triangles = len(mesh.loops) - 2 * len(mesh.polygons)
    required = memory.estimate_bytes(
        len(mesh.vertices), len(mesh.edges) + triangles - len(mesh.polygons), triangles, options.levels,
        uv_layers=len(mesh.uv_layers), limit_surface=options.use_limit_surface, version=bpy.app.version,
        drawn=not bpy.app.background)
    available = memory.available_bytes()
    if not memory.fits(required, available):
        raise LoopSubError(memory.describe(required, available, options.levels))


class Result:
    """A subdivided mesh data-block, built but not yet on the object, and what the artist should be told."""

    def __init__(self, mesh, messages, group_names, group_locks, active_group):
        self.mesh = mesh
        self.messages = messages
        self.group_names = group_names
        self.group_locks = group_locks
        self.active_group = active_group


class Refined:
    """What a plan's evaluation gives for one Source: the vertex channels (N_out, C), the UV maps per output corner
    (one (T_out, 3, 2) array each), the linear corner channels (T_out, 3, C) or None, the limit normals per output
    corner (T_out, 3, 3), None without the limit surface, and the output triangles (the plan's). A UV map or the
    corner channels left as the result holds them (Source.refine's written) are None."""

    def __init__(self, vertex, uvs, corners, normals, triangles):
        self.vertex = vertex
        self.uvs = uvs
        self.corners = corners
        self.normals = normals
        self.triangles = triangles


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
    are the notes (messages) altogether, since the result is then only updated.

    exact_normals: with the limit surface, write the limit normals as custom split normals (Apply, renders); False
    (the live entry in the viewport, while it changes) leaves the normals to Blender, with the edges across which the
    limit normals split marked sharp, which Blender takes and evaluates several times faster (Source.blender_normals;
    write_limit_normals puts the limit normals in afterwards)."""

    def __init__(self, obj, mesh, options, checked_triangles=None, exact_normals=True):
        self.mesh = mesh
        self.options = options
        self.exact_normals = exact_normals
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
                | compat.crease_attribute_names() | compat.seam_and_normal_attribute_names()
                | {uv.name for uv in mesh.uv_layers})
        self.point, self.corner, self.face, self.edge, dropped = geometry.plan_attributes(
            [(a.name, a.domain, a.data_type) for a in mesh.attributes], skip)
        if dropped:
            self.messages.append(('WARNING', f"{obj.name}: attributes not carried over: "
                                        + ", ".join(f"{n} ({d.lower()} {t.lower()})" for n, d, t in dropped)))

        # Vertex channels: positions, point attributes and vertex groups refine together with the same weights.
        self.vertex = _Channels()
        self.vertex.add("position", cage.positions)
        for name, _, _ in self.point:
            self.vertex.add(("attribute", name), _get_attribute(mesh.attributes[name], cage.num_vertices))
        self.vertex.add("groups", self.group_weights)

        # Edge data passes to the child edges on each cage edge: seam and sharp marks, edge attributes.
        self.edge_flags = {prop: _get(mesh.edges, prop, len(mesh.edges), 1, np.bool_)
                           for prop in ("use_seam", "use_edge_sharp")}
        self.edge_values = [_get_attribute(mesh.attributes[name], len(mesh.edges)) for name, _, _ in self.edge]

        # UV maps: face-varying layers with their own topology (a seam splits the value, not the vertex), refined as
        # UV Smooth says, to the limit with the limit surface.
        self.uv_names = [uv.name for uv in mesh.uv_layers]
        self.uv_layers = [geometry.weld_corner_values(cage.triangles, _get(uv.data, "uv", cage.num_loops, 2,
                                                                          np.float32)[cage.triangle_loops])
                          for uv in mesh.uv_layers]

        # Corner channels refined linearly per face: corner attributes, and custom split normals where the mesh
        # shades with them (they then take the place of the limit normals).
        self.corners = _Channels()
        for name, _, _ in self.corner:
            self.corners.add(("attribute", name),
                             _get_attribute(mesh.attributes[name], cage.num_loops)[cage.triangle_loops])
        self.custom_normals = compat.custom_normals_in_use(mesh)
        self.free_normals = self.custom_normals and compat.has_free_normals(mesh)  # 4.5+: the result's are free too
        if self.custom_normals:
            self.corners.add("normal", compat.read_corner_normals(mesh)[cage.triangle_loops])
        # The result shades with the limit normals as custom split normals, on smooth faces; or, for the viewport,
        # with Blender's own normals, split where the limit normals split.
        self.limit_normals = options.use_limit_surface and not self.custom_normals
        self.blender_normals = self.limit_normals and not exact_normals
        self.auto_loops = None  # result corners that keep Blender's own normal (build_mesh sets it)

        self.materials = _get(mesh.polygons, "material_index", cage.num_polygons, 1, np.int32)
        self.smooth = _get(mesh.polygons, "use_smooth", cage.num_polygons, 1, np.bool_)
        self.face_values = [_get_attribute(mesh.attributes[name], cage.num_polygons) for name, _, _ in self.face]
        if not known:
            self.messages += _normal_notes(obj.name, mesh, self)

    def plan_key(self):
        """What the plan depends on: equal keys, equal plans."""
        return (self.options, self.cage.triangles, *self.cage.tags(self.options).values(), self.cones,
                *(indices for indices, _ in self.uv_layers))

    def layout_key(self):
        """What, besides the plan, fixes the result's structure and its non-interpolated data: while it and the plan
        stay the same, a result can be updated in place (update_mesh) instead of built anew."""
        return (tuple(self.point), tuple(self.corner), tuple(self.face), tuple(self.uv_names), self.custom_normals,
                self.free_normals, self.limit_normals, self.blender_normals,
                tuple(self.edge), tuple(self.group_names), self.group_weights, self.materials, self.smooth,
                *self.face_values, *self.edge_values, *self.edge_flags.values(), self.cage.edge_weights,
                self.cage.vertex_weights)

    def plan(self, levels=None):
        return self.cage.plan(self.options, self.options.levels if levels is None else levels, self.cones,
                              [indices for indices, _ in self.uv_layers])

    def inputs(self):
        """The values a refinement reads (for the live entry: equal inputs on the same plan, equal result)."""
        return (self.vertex.packed(), self.corners.packed() if self.corners.parts else None,
                *(values for _, values in self.uv_layers))

    def refine(self, plan, written=None):
        """Evaluates plan (built from this source's plan key) on the source's values: a Refined. written: the inputs
        (Source.inputs) of the result it updates in place; the UV maps and corner channels whose values are still
        those are not refined again (None in the Refined): the result holds them already, and playback moves only
        positions."""
        def unchanged(index, values):  # index: the place of values in Source.inputs
            return written is not None and np.array_equal(written[index], values)

        normals = None
        if self.options.use_limit_surface:
            # Positions come first among the vertex channels; the others are refined with the same limit weights.
            vertex, normals = native.run(plan.evaluate_with_normals, self.vertex.packed())
        else:
            vertex = native.run(plan.evaluate, self.vertex.packed())
        uvs = [None if unchanged(2 + layer, values)
               else native.run(plan.evaluate_face_varying, values, layer=layer)[plan.face_varying_indices(layer)]
               for layer, (_, values) in enumerate(self.uv_layers)]
        corners = None
        if self.corners.parts:
            values = self.corners.packed()
            # The cage's custom normals are written on every update (update_mesh): in tangent space they are stored
            # relative to the result's geometry, which may have moved. Free normals (4.5+) do not change when
            # vertices move, nor does any corner value when only a UV does.
            corners = (None if unchanged(1, values) and not self.custom_normals
                       else native.run(plan.evaluate_face_varying, values))
        return Refined(vertex, uvs, corners, normals, plan.triangles)


# The long stages of subdivide, in order (the progress counter at the cursor counts them).
STAGES = ("Reading the mesh", "Building the plan", "Refining", "Writing the new mesh")


def subdivide(obj, options, progress):
    """Builds the subdivided copy of obj's own mesh (for Apply). progress(k) is called as stage STAGES[k] begins."""
    check_object(obj)
    progress(0)
    source = Source(obj, obj.data, options)
    progress(1)
    plan = source.plan()
    progress(2)
    refined = source.refine(plan)
    progress(3)
    new = build_mesh(source, plan, refined, obj.data.name, None)
    locks = [group.lock_weight for group in obj.vertex_groups]
    return Result(new, source.messages, source.group_names, locks, obj.vertex_groups.active_index)


def build_mesh(source, plan, refined, name, holder):
    """A new mesh data-block with the subdivision: geometry, face data, attributes, creases, UVs, normals, vertex
    groups, tags. refined: source.refine(plan). holder: an object whose data the new mesh may become while vertex
    groups are written (None: a temporary one). Sets source.auto_loops, which update_mesh takes."""
    mesh, cage, options = source.mesh, source.cage, source.options
    vertex = source.vertex
    new = bpy.data.meshes.new(name)
    try:
        for material in mesh.materials:
            # An evaluated input lists evaluated copies of its materials, which a saved file cannot keep.
            new.materials.append(material.original if material is not None else None)
        compat.copy_shading_settings(mesh, new)
        if len(plan.corner_vertices) or compat.has_vertex_creases(mesh):
            compat.add_vertex_crease_layer(new)  # while the mesh is empty: cheap on every Blender version
        new_edges, triangle_edges = _write_geometry(new, refined.vertex[:, vertex.columns["position"]], plan)
        parents = cage.triangle_polygons[plan.parent_triangles]
        _write_face_data(new, source, parents)
        _write_creases(new, cage, plan, options, new_edges)
        sharp = _write_edge_data(new, source, plan, new_edges)
        if source.blender_normals:
            _mark_limit_splits(new, source, plan, new_edges, triangle_edges, sharp)
        source.auto_loops = _auto_loops(source, plan, new_edges, sharp, parents)
        _add_value_layers(new, source)
        _write_values(new, source, refined)
        new.update()
        _write_normals(new, source, refined, source.auto_loops)
        _write_vertex_groups(new, source, refined.vertex[:, vertex.columns["groups"]], holder)
        _write_plan_tags(new, plan, new_edges)
    except Exception:
        bpy.data.meshes.remove(new)
        raise
    return new


def update_mesh(new, source, refined, auto_loops):
    """Writes new values into a result that build_mesh made from a source with the same plan and layout keys: the
    positions, point attributes, UVs, corner attributes and normals (what moving vertices in Edit Mode or animation
    changes). auto_loops: the source.auto_loops of that build."""
    new.vertices.foreach_set("co", np.ascontiguousarray(refined.vertex[:, source.vertex.columns["position"]]).ravel())
    _write_values(new, source, refined)
    new.update()
    _write_normals(new, source, refined, auto_loops)  # nothing to write with Blender's normals: they follow


def _add_value_layers(new, source):
    """The layers that _write_values fills, empty: point and corner attributes, and the UV maps with the cage's
    active and render choices."""
    for name, domain, data_type in (*source.point, *source.corner):
        new.attributes.new(name, data_type, domain)
    mesh = source.mesh
    for uv in mesh.uv_layers:
        new.uv_layers.new(name=uv.name, do_init=False).active_render = uv.active_render
    new.uv_layers.active_index = mesh.uv_layers.active_index
    _restore_color_choice(new, mesh)


def _write_values(new, source, refined):
    """The refined values besides positions, into their layers: point attributes (back to their types), UV maps and
    corner attributes (one value per loop, 3 per triangle)."""
    vertex, corners = source.vertex, source.corners
    for name, _, data_type in source.point:
        _fill(new.attributes[name], data_type,
              geometry.from_refined(refined.vertex[:, vertex.columns["attribute", name]], data_type))
    for uv_name, uvs in zip(source.uv_names, refined.uvs):
        if uvs is not None:
            new.uv_layers[uv_name].data.foreach_set("uv", np.ascontiguousarray(uvs).ravel())
    for name, _, data_type in source.corner if refined.corners is not None else ():
        _fill(new.attributes[name], data_type, refined.corners[:, :, corners.columns["attribute", name]])


def _auto_loops(source, plan, new_edges, sharp, parents):
    """(T_out, 3) bool, or None: the result's corners that keep Blender's own normal (a zero custom normal) with the
    limit normals: those of flat faces (children of the cage's flat-shaded faces: flat, as Subdivision Surface keeps
    them with Use Limit Surface on), and those at vertices on marked sharp edges, where the mesh shades with them (Auto
    Smooth up to 4.0), so that a marked sharp edge still shows as one."""
    if not source.limit_normals:
        return None
    loops = None
    if sharp is not None and sharp.any() and compat.shades_sharp_edges(source.mesh):
        on_sharp = np.zeros(plan.num_output_vertices, dtype=bool)
        on_sharp[new_edges[sharp].ravel()] = True
        loops = on_sharp[plan.triangles]
    flat = ~source.smooth[parents]
    if flat.any():
        loops = np.repeat(flat[:, None], 3, axis=1) if loops is None else loops | flat[:, None]
    return loops


def _mark_limit_splits(new, source, plan, new_edges, triangle_edges, sharp):
    """Blender's normals in place of the limit normals (the viewport): the edges across which the limit normals split
    are marked sharp, beside the cage's marked sharp edges, and shade so (Auto Smooth on, at 180 degrees when the cage
    had it off); where nothing splits, the mesh shades smooth with Blender's vertex normals, and Auto Smooth stays as
    the cage had it.

    Where the limit normals split depends on the plan alone (the sides of crease, corner and boundary vertices), not
    on the positions, but a flat crease gives both sides the same normal: the split is found from the limit normals
    of generic positions (a fixed pseudo-random cage), where every side has a normal of its own."""
    probe = np.random.default_rng(1).random((source.cage.num_vertices, 3), dtype=np.float32)
    _, normals = native.run(plan.evaluate_with_normals, probe)
    split = geometry.split_normal_edges(triangle_edges, normals, new_edges, plan.triangles)
    if not split.any():
        return
    marked = split if sharp is None else split | sharp
    new.edges.foreach_set("use_edge_sharp", marked)
    compat.shade_sharp_edges(new)


def _write_normals(new, source, refined, auto_loops):
    """Custom split normals: the cage's own, interpolated linearly per face (normalised), where it shades with
    them (free normals stay free, 4.5+); else, with the limit surface, the limit normals (split across creases and
    boundaries, shared elsewhere), unless the result shows Blender's own normals (Source.blender_normals), which need
    nothing written."""
    if source.blender_normals:
        return
    if source.custom_normals:
        normals = np.array(refined.corners[:, :, source.corners.columns["normal"]], dtype=np.float32)
        lengths = np.linalg.norm(normals, axis=2, keepdims=True)
        np.divide(normals, lengths, out=normals, where=lengths > 0)
        if source.free_normals:
            compat.set_custom_normals(new, normals, free=True)
            return
    elif source.limit_normals:
        write_limit_normals(new, refined.normals, refined.triangles, auto_loops)
        return
    else:
        return
    _set_normals(new, normals, refined.triangles, None)


def write_limit_normals(new, normals, triangles, auto_loops):
    """The limit normals (T_out, 3, 3) as custom split normals, but Blender's own at auto_loops (see _auto_loops).
    Also what the live entry writes into a result that showed Blender's normals, once it is still (live.py)."""
    if auto_loops is not None:
        if auto_loops.all():
            return  # every face flat: Blender's own normals are the face normals
        normals = np.where(auto_loops[:, :, None], np.float32(0), normals)
    _set_normals(new, normals, triangles, auto_loops)


def _set_normals(new, normals, triangles, auto_loops):
    # One normal per vertex where no crease splits them, several times faster for Blender to take; not with corners
    # that keep Blender's own normal (from vertices, Blender then gives a marked sharp edge's sides one normal).
    shared = (geometry.shared_vertex_normals(triangles, normals, len(new.vertices))
              if auto_loops is None else None)
    compat.set_custom_normals(new, normals, shared)


def shading_state(mesh):
    """What write_limit_normals may change in a result's shading besides the normals, for show_blender_normals to
    put back (compat.shading_state)."""
    return compat.shading_state(mesh)


def show_blender_normals(new, holder, state):
    """Back from write_limit_normals to Blender's own normals: the custom split normals removed (Blender's operator,
    on holder, an object whose data new is), the shading as it was (state, from shading_state)."""
    compat.clear_custom_normals(new, holder)
    compat.restore_shading_state(new, state)


def _write_geometry(new, positions, plan):
    """Vertices, edges and triangles. The edges come numbered from the core's refinement (geometry.output_edges), so
    Blender need not find them, nor the add-on read them back. Returns (edge_vertices, triangle_edges)."""
    triangles = plan.triangles
    num_triangles = len(triangles)
    edges, triangle_edges = geometry.output_edges(triangles, plan.level_edges(plan.levels - 1),
                                                  plan.level_num_vertices(plan.levels - 1))
    new.vertices.add(len(positions))
    new.vertices.foreach_set("co", np.ascontiguousarray(positions).ravel())
    new.edges.add(len(edges))
    new.edges.foreach_set("vertices", edges.ravel())
    new.loops.add(3 * num_triangles)
    new.loops.foreach_set("vertex_index", np.ascontiguousarray(triangles, dtype=np.int32).ravel())
    new.loops.foreach_set("edge_index", triangle_edges.ravel())
    new.polygons.add(num_triangles)
    compat.set_polygon_loops(new, np.arange(num_triangles, dtype=np.int32) * 3, np.full(num_triangles, 3, np.int32))
    new.update()
    return edges, triangle_edges


def _write_face_data(new, source, parent_polygons):
    """Per-face data comes from the parent face of the cage (through its triangle), flat/smooth shading too (with the
    limit normals as well: they show on the smooth faces, as Subdivision Surface keeps flat faces flat). Material
    indices go through their attribute (Blender 3.4+), many times faster than MeshPolygon.material_index; like
    Blender, none is written when every face uses the first slot."""
    materials = source.materials[parent_polygons]
    if materials.any():
        _set_attribute(new, "material_index", 'FACE', 'INT', materials)
    new.polygons.foreach_set("use_smooth", np.ascontiguousarray(source.smooth[parent_polygons]))
    for (name, domain, data_type), values in zip(source.face, source.face_values):
        _set_attribute(new, name, domain, data_type, values[parent_polygons])


def _write_creases(new, cage, plan, options, new_edges):
    """Child creases: the core's decremented sharpness (OpenSubdiv) or carried weights (seed rules), as weights."""
    num_vertices = len(new.vertices)
    edge_weights = np.zeros(len(new_edges), dtype=np.float32)
    found = geometry.lookup_edges(new_edges, plan.crease_edges, num_vertices)
    edge_weights[found[found >= 0]] = geometry.child_crease_weights(plan.crease_sharpness[found >= 0], options.rules)
    if len(found) or cage.edge_weights.any():
        compat.write_edge_creases(new, edge_weights)
    vertex_weights = np.zeros(num_vertices, dtype=np.float32)
    vertex_weights[plan.corner_vertices] = geometry.child_crease_weights(plan.corner_sharpness, options.rules)
    if compat.has_vertex_creases(new):
        compat.write_vertex_creases(new, vertex_weights)


def _write_edge_data(new, source, plan, new_edges):
    """Seam and sharp marks and edge attributes pass to the child edges that lie on a cage edge; edges inside a cage
    face get none (zero, false). Returns the child edges' sharp marks (None when there are none)."""
    flags = {prop: values for prop, values in source.edge_flags.items() if values.any()}
    if not flags and not source.edge:
        return None
    cage = source.cage
    parents = geometry.parent_edges(new_edges, [plan.level_edges(level) for level in range(plan.levels)],
                                    [plan.level_num_vertices(level) for level in range(plan.levels)],
                                    cage.edge_vertices, cage.num_vertices)
    inherited = {prop: geometry.inherit_edge_values(values, parents) for prop, values in flags.items()}
    for prop, values in inherited.items():
        new.edges.foreach_set(prop, values)
    for (name, domain, data_type), values in zip(source.edge, source.edge_values):
        _set_attribute(new, name, domain, data_type, geometry.inherit_edge_values(values, parents))
    return inherited.get("use_edge_sharp")


def _restore_color_choice(new, mesh):
    colors = new.color_attributes
    active = mesh.color_attributes.active_color
    if active is not None and active.name in colors:
        colors.active_color = colors[active.name]
    if mesh.color_attributes.default_color_name in colors:
        colors.render_color_index = colors.find(mesh.color_attributes.default_color_name)


def _write_vertex_groups(new, source, refined_groups, holder):
    """Vertex groups through Blender's Convert Attribute operator, which writes the weights in C (the API has no
    bulk setter); it works on an object, the holder (a temporary one when None). The cone group holds tags, not
    weights: it stays on the cage's vertices, which keep their indices."""
    if not source.group_names:
        return
    temporary = holder is None
    if temporary:
        holder = bpy.data.objects.new("Loop Subdivision (temporary)", new)
    else:
        holder.data = new
    try:
        holder.vertex_groups.clear()
        for index, name in enumerate(source.group_names):
            if index == source.cone_index:
                weights = np.zeros(len(new.vertices), dtype=np.float32)
                weights[:len(source.group_weights)] = source.group_weights[:, index]
            else:
                weights = np.clip(refined_groups[:, index], 0.0, 1.0)
            attribute = _set_attribute(new, _GROUP_TRANSFER, 'POINT', 'FLOAT', weights)
            new.attributes.active = attribute
            # Convert Attribute refuses while any object is in Edit Mode (its poll reads the context's edit object,
            # in every version): the modifier rebuilds in Edit Mode too, on a holder that is not being edited.
            with bpy.context.temp_override(object=holder, active_object=holder, edit_object=None):
                bpy.ops.geometry.attribute_convert(mode='VERTEX_GROUP')
            holder.vertex_groups[index].name = name
    finally:
        if temporary:
            bpy.data.objects.remove(holder)


def replace_mesh(obj, result):
    """Swaps the built mesh in; the old data-block goes when nothing else uses it (undo brings it back)."""
    old = obj.data
    name = old.name
    obj.data = result.mesh
    for group, lock in zip(obj.vertex_groups, result.group_locks):
        group.lock_weight = lock
    obj.vertex_groups.active_index = result.active_group
    if old.users == 0:
        bpy.data.meshes.remove(old)
    result.mesh.name = name


def write_tags(mesh, topology, options, cones):
    """Writes what the rules derive from the crease weights of a cage: "loop_crease" (edges) and "loop_vertex_type"
    (points), both from the core's plan of its first level."""
    if not len(topology.triangles):
        raise LoopSubError(f"\"{mesh.name}\" has no faces to tag")
    # The classes of level 0 come from a plan of one level; its sharp edges from a plan of none (its output is the
    # cage itself).
    types = np.asarray(topology.plan(_classifying(options), 1, cones).level_vertex_types(0), dtype=np.int32)
    _replace_tags(mesh, _sharp_edge_mask(topology.plan(_classifying(options), 0, cones), topology.edge_vertices,
                                         topology.num_vertices), types)


def _write_plan_tags(mesh, plan, edges):
    """The tags of a result, from the plan that made it: the classes its vertices take at the next level and the edges
    its rules treat as sharp (tagged creases that pass them, boundary and non-manifold edges). No second
    classification: refining the result further uses exactly these."""
    _replace_tags(mesh, _sharp_edge_mask(plan, edges, len(mesh.vertices)),
                  np.asarray(plan.level_vertex_types(plan.levels), dtype=np.int32))


def _sharp_edge_mask(plan, edges, num_vertices):
    """Which of `edges` (vertex pairs of the plan's output) the plan's rules treat as sharp."""
    mask = np.zeros(len(edges), dtype=bool)
    found = geometry.lookup_edges(edges, np.asarray(plan.sharp_edges), num_vertices)
    mask[found[found >= 0]] = True
    return mask


def _replace_tags(mesh, creases, types):
    for name, domain, data_type, values in ((CREASE_TAG, 'EDGE', 'BOOLEAN', creases),
                                            (VERTEX_TYPE_TAG, 'POINT', 'INT', types)):
        existing = mesh.attributes.get(name)
        if existing is not None:
            mesh.attributes.remove(existing)
        _set_attribute(mesh, name, domain, data_type, values)


def tag_object(obj, options):
    """The Refresh Tags operator's work on one object (its own mesh, in place)."""
    if obj.data.is_editmode:
        raise LoopSubError(f"{obj.name} is in Edit Mode")
    cage = Cage(obj.data)
    cage.validate(obj.name)
    cone_index = cone_group_index(obj, options)
    weights = read_vertex_groups(obj.data, cone_index + 1) if cone_index is not None else None
    write_tags(obj.data, cage, options, cone_vertices(weights, cone_index))
