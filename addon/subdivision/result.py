"""Building the subdivided mesh from a Source and its plan: a new data-block for Apply and the live entry, or new
values written into one already built (update_mesh).

Apply builds the subdivided mesh completely in a new data-block and only then swaps it in, so any error leaves the
object's mesh untouched.
"""
import bpy
import numpy as np

from ..blender import creases, mesh_arrays, shading
from ..blender.mesh_arrays import add_attribute, fill_attribute
from ..model import geometry, memory
from . import adaptive, normals
from .cage import Source, check_memory, check_object
from .refinement import Destination, PlanOutput, refine

# Temporary name of a float point attribute on its way to becoming a vertex group.
_GROUP_TRANSFER = "loop_subdivision_group_transfer"


class Result:
    """A subdivided mesh data-block, built but not yet on the object, and what the artist should be told."""

    def __init__(self, mesh, messages, group_names, group_locks, active_group):
        self.mesh = mesh
        self.messages = messages
        self.group_names = group_names
        self.group_locks = group_locks
        self.active_group = active_group


# The long stages of subdivide, in order (the progress counter at the cursor counts them). The new mesh is refined
# into as it is built.
STAGES = ("Reading the mesh", "Building the plan", "Building the new mesh")


def subdivide(obj, options, progress, view=None):
    """Builds the subdivided copy of obj's own mesh (for Apply). progress(k) is called as stage STAGES[k] begins.
    view: the adaptive.View that Adaptive Subdivision cuts for."""
    check_object(obj)
    progress(0)
    source = Source(obj, obj.data, options)
    progress(1)
    if options.use_adaptive:
        edge_rates = adaptive.rates(source.cage, options, view, obj.matrix_world)
        output = adaptive.tessellate(source, edge_rates)
    else:
        check_memory(source)
        output = PlanOutput(source.plan())
    progress(2)
    new = build_mesh(source, output, obj.data.name)
    locks = [group.lock_weight for group in obj.vertex_groups]
    return Result(new, source.messages, source.group_names, locks, obj.vertex_groups.active_index)


def build_mesh(source, output, name):
    """A new mesh data-block with the subdivision: geometry, face data, attributes, creases, UVs, normals, vertex
    groups, tags. output: its structure (output.PlanOutput or TessellationOutput), refined straight into the new
    mesh's arrays where it can (refinement.Destination). Sets source.blender_corners, which update_mesh takes."""
    mesh, cage, options = source.mesh, source.cage, source.options
    vertex = source.vertex
    new = bpy.data.meshes.new(name)
    try:
        for material in mesh.materials:
            # An evaluated input lists evaluated copies of its materials, which a saved file cannot keep.
            new.materials.append(material.original if material is not None else None)
        shading.copy_shading_settings(mesh, new)
        if output.has_vertex_creases() or creases.has_vertex_creases(mesh):
            creases.add_vertex_crease_layer(new)  # while the mesh is empty: cheap on every Blender version
        new_edges = _write_structure(new, output)
        # Each face's cage face, where face values differ between cage faces: a gather of a million entries or more.
        parents = (cage.triangle_polygons[output.parent_triangles]
                   if source.materials.any() or not source.smooth.all() or source.face else None)
        _write_face_data(new, source, parents)
        _write_creases(new, cage, output, options, new_edges)
        sharp = _write_edge_data(new, source, output, new_edges)
        source.blender_corners = normals.blender_normal_corners(source, output, new_edges, sharp, parents)
        refined = refine(output, source, into=Destination(mesh_arrays.position_array(new),
                                                         normals.vertex_normal_destination(new, source, output)))
        mesh_arrays.write_positions(new, refined.vertex[:, vertex.columns["position"]])
        _add_value_layers(new, source)
        _write_values(new, source, refined)
        new.update()
        normals.write_normals(new, source, refined, source.blender_corners)
        _write_vertex_groups(new, source, output)
        output.write_tags(new, len(new_edges))
    except Exception:
        bpy.data.meshes.remove(new)
        raise
    return new


def update_mesh(new, source, refined, blender_corners):
    """Writes new values into a result that build_mesh made from a source with the same plan and layout keys: the
    positions, point attributes, UVs, corner attributes and normals (what moving vertices in Edit Mode or animation
    changes). blender_corners: the source.blender_corners of that build."""
    mesh_arrays.write_positions(new, refined.vertex[:, source.vertex.columns["position"]])
    _write_values(new, source, refined)
    new.update()
    normals.write_normals(new, source, refined, blender_corners)


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
        fill_attribute(new.attributes[name], data_type,
              geometry.from_refined(refined.vertex[:, vertex.columns["attribute", name]], data_type))
    for uv_name, uvs in zip(source.uv_names, refined.uvs):
        if uvs is not None:
            mesh_arrays.write_uvs(new, uv_name, uvs)
    for name, _, data_type in source.corner if refined.corners is not None else ():
        fill_attribute(new.attributes[name], data_type, refined.corners[:, :, corners.columns["attribute", name]])


def _write_structure(new, output):
    """Vertices (their positions to come), edges and triangles. The edges come from the output (a plan numbers them
    as it refines), so Blender need not find them, nor the add-on read them back. Returns the edges' vertices (E,
    2)."""
    num_triangles = len(output.triangles)
    new.vertices.add(output.num_vertices)
    new.edges.add(output.num_edges())
    new.loops.add(3 * num_triangles)
    edges = output.write_edges(new)
    new.polygons.add(num_triangles)
    mesh_arrays.set_triangle_loops(new)
    new.update()
    return edges


def _write_face_data(new, source, parent_polygons):
    """Per-face data comes from the parent face of the cage (through its triangle; parent_polygons None where every
    cage face is smooth, of the first material and without face attributes), flat/smooth shading too (with the limit
    normals as well: they show on the smooth faces, as Subdivision Surface keeps flat faces flat). Material indices go
    through their attribute (Blender 3.4+), many times faster than MeshPolygon.material_index; like Blender, none is
    written when every face uses the first slot."""
    if source.materials.any():
        materials = source.materials[parent_polygons]
        if materials.any():
            add_attribute(new, "material_index", 'FACE', 'INT', materials)
    mesh_arrays.write_smooth(new, None if source.smooth.all() else source.smooth[parent_polygons])
    for (name, domain, data_type), values in zip(source.face, source.face_values):
        add_attribute(new, name, domain, data_type, geometry.take_rows(values, parent_polygons))


def _write_creases(new, cage, output, options, new_edges):
    """The result's crease weights (output.creases): an edge crease layer where the cage has one (only its creased
    edges give creased ones), vertex creases where build_mesh added their layer. Nothing is worked out for a cage
    without creases."""
    edge_layer, vertex_layer = cage.edge_weights.any(), creases.has_vertex_creases(new)
    if not edge_layer and not vertex_layer:
        return
    edge_weights, vertex_weights = output.creases(cage, options, new_edges)
    if edge_layer:
        creases.write_edge_creases(new, edge_weights)
    if vertex_layer:
        creases.write_vertex_creases(new, vertex_weights)


def _write_edge_data(new, source, output, new_edges):
    """Seam and sharp marks and edge attributes pass to the child edges that lie on a cage edge; edges inside a cage
    face get none (zero, false). Returns the child edges' sharp marks (None when there are none)."""
    flags = {prop: values for prop, values in source.edge_flags.items() if values.any()}
    if not flags and not source.edge:
        return None
    # As numpy's own index type once: np.take converts int32 indices on every call (a million and more here).
    parents = np.asarray(output.edge_parents(new_edges, source.cage), dtype=np.intp)
    inherited = {prop: geometry.inherit_edge_values(values, parents) for prop, values in flags.items()}
    mesh_arrays.write_edge_flags(new, inherited)
    for (name, domain, data_type), values in zip(source.edge, source.edge_values):
        add_attribute(new, name, domain, data_type, geometry.inherit_edge_values(values, parents))
    return inherited.get("use_edge_sharp")


def _restore_color_choice(new, mesh):
    colors = new.color_attributes
    active = mesh.color_attributes.active_color
    if active is not None and active.name in colors:
        colors.active_color = colors[active.name]
    if mesh.color_attributes.default_color_name in colors:
        colors.render_color_index = colors.find(mesh.color_attributes.default_color_name)


def _write_vertex_groups(new, source, output):
    """Vertex groups through Blender's Convert Attribute operator, which writes the weights in C (the API has no
    bulk setter) and only those above zero. It works on an object: a temporary one that no scene holds, since each
    call evaluates the depsgraph, which would evaluate again whatever shows the new mesh (the live entry's helper, at
    1.3 million triangles: 47 ms a group against 7). The weights are refined memory.GROUP_BATCH groups at a time: a
    rig's hundreds of groups, refined at once, would hold four bytes per group and output vertex where Blender keeps
    the few above zero. The cone group holds tags, not weights: it stays on the cage's vertices, which keep their
    indices. The groups' names are the mesh's (Blender 3.0 on), whichever object shows it next."""
    if not source.group_names:
        return
    holder = bpy.data.objects.new("Loop Subdivision (temporary)", new)
    try:
        holder.vertex_groups.clear()
        refined, first = None, 0
        for index, name in enumerate(source.group_names):
            if index == source.cone_index:
                weights = np.zeros(len(new.vertices), dtype=np.float32)
                weights[:len(source.group_weights)] = source.group_weights[:, index]
            else:
                if refined is None or index >= first + refined.shape[1]:
                    first = index
                    batch = source.group_weights[:, first:first + memory.GROUP_BATCH]
                    refined = output.refine_vertex_values(np.ascontiguousarray(batch)).reshape(len(new.vertices), -1)
                weights = np.clip(refined[:, index - first], 0.0, 1.0)
            attribute = add_attribute(new, _GROUP_TRANSFER, 'POINT', 'FLOAT', weights)
            new.attributes.active = attribute
            # Convert Attribute refuses while any object is in Edit Mode (its poll reads the context's edit object,
            # in every version): the modifier rebuilds in Edit Mode too, on a holder that is not being edited.
            with bpy.context.temp_override(object=holder, active_object=holder, edit_object=None):
                bpy.ops.geometry.attribute_convert(mode='VERTEX_GROUP')
            holder.vertex_groups[index].name = name
    finally:
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
