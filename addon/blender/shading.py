"""Normals and shading, as each version keeps them: 4.0 has Mesh.corner_normals but fills it only after
calc_normals_split(); 4.1 dropped Auto Smooth (custom split normals and marked sharp edges always shade), replaced
Mesh.calc_normals_split / MeshLoop.normal with Mesh.corner_normals, and converts the Auto Smooth of files saved before
it into appended "Auto Smooth" modifiers; 4.5 keeps custom normals in the attribute "custom_normal" (tangent space, or
"free" float vectors).
"""
import ctypes
import math

import bpy
import numpy as np

from . import memory_views
from .mesh_arrays import CUSTOM_NORMAL_ATTRIBUTE, NAMES_SEAMS_AND_NORMALS

# Free normals: Blender shades with them as they are (4.5+); set_custom_normals writes them with one copy, where
# tangent-space normals cost Blender's normal spaces on every write (docs/benchmark.md, by version).
HAS_FREE_NORMALS = NAMES_SEAMS_AND_NORMALS


def has_free_normals(mesh):
    """Whether the mesh shades with free custom normals (4.5+): a float vector "custom_normal", on any domain."""
    attribute = mesh.attributes.get(CUSTOM_NORMAL_ATTRIBUTE) if NAMES_SEAMS_AND_NORMALS else None
    return attribute is not None and attribute.data_type == 'FLOAT_VECTOR'


def free_vertex_normal_array(mesh):
    """A new mesh's free normals, one per vertex (HAS_FREE_NORMALS): its new point attribute "custom_normal", as a
    writable (V, 3) float32 view of its memory for the core to evaluate into; set_custom_normals then finds them in
    place. None before 4.5 (no attribute added), or where the attribute's items are not one array (the attribute
    stays, for set_custom_normals to fill)."""
    if not HAS_FREE_NORMALS:
        return None
    attribute = mesh.attributes.new(CUSTOM_NORMAL_ATTRIBUTE, 'FLOAT_VECTOR', 'POINT')
    return memory_views.attribute_array(attribute, len(mesh.vertices), 3, ctypes.c_float)


def copy_shading_settings(source, target):
    """What a mesh says about its shading besides per-face flags: Auto Smooth up to 4.0 (4.1 dropped it for a
    modifier), and its custom properties."""
    if hasattr(source, "use_auto_smooth"):
        target.use_auto_smooth = source.use_auto_smooth
        target.auto_smooth_angle = source.auto_smooth_angle
    for key in source.keys():
        value = source[key]
        target[key] = value.original if isinstance(value, bpy.types.ID) else value


def shades_sharp_edges(mesh):
    """Whether custom split normals and marked sharp edges show in the mesh's shading: with Auto Smooth up to 4.0,
    always from 4.1."""
    return getattr(mesh, "use_auto_smooth", True)


def shade_sharp_edges(mesh):
    """Makes marked sharp edges (and custom split normals) shade: up to 4.0 they do only with Auto Smooth, which this
    turns on; a mesh that had it off gets the widest angle, so that only the marks split the shading. From 4.1 they
    always do."""
    if hasattr(mesh, "use_auto_smooth") and not mesh.use_auto_smooth:
        mesh.use_auto_smooth = True
        mesh.auto_smooth_angle = math.pi


def custom_normals_in_use(mesh):
    return mesh.has_custom_normals and shades_sharp_edges(mesh)


def own_corner_normals(mesh):
    """The normals Blender gives a mesh's corners of itself, (L, 3) float32: split at marked sharp edges, the face
    normal on a flat face. Free normals it has go first (4.5+: a result's own, written again after)."""
    existing = mesh.attributes.get(CUSTOM_NORMAL_ATTRIBUTE) if NAMES_SEAMS_AND_NORMALS else None
    if existing is not None:
        mesh.attributes.remove(existing)
    return read_corner_normals(mesh)


def read_corner_normals(mesh):
    """The normal Blender shades each corner (loop) with, custom split normals included: (L, 3) float32.

    4.1+ has them in Mesh.corner_normals; up to 4.0 Mesh.calc_normals_split() computes them into MeshLoop.normal.
    4.0 has Mesh.corner_normals too, but it is empty until calc_normals_split() has run (its length is that of the
    CD_NORMAL layer, rna_mesh.cc), so the version decides, not hasattr, and a length that is not the number of corners
    takes the old way as well. No 4.0 is installed here: that branch is read from Blender's sources, not tested.

    Free normals (4.5+) are read from their attribute, spread to the corners: that is what Blender shades with
    (Mesh.corner_normals gives the attribute's values as they are, unnormalised, whatever the faces' smooth flags),
    and Mesh.corner_normals of a copy from Object.to_mesh() of a mesh with free corner normals, what the live entry
    reads its input from, gave stale memory at a few corners in 4.5.15 and 5.0.1 (zeros, denormals, NaN; not seen in
    5.2.3)."""
    free = _free_corner_normals(mesh)
    if free is not None:
        return free
    values = np.empty(len(mesh.loops) * 3, dtype=np.float32)
    corner_normals = getattr(mesh, "corner_normals", None) if bpy.app.version >= (4, 1, 0) else None
    if corner_normals is not None and len(corner_normals) == len(mesh.loops):
        corner_normals.foreach_get("vector", values)
    else:
        mesh.calc_normals_split()
        mesh.loops.foreach_get("normal", values)
        mesh.free_normals_split()
    return values.reshape(-1, 3)


def _free_corner_normals(mesh):
    """The free normals of mesh per corner (L, 3) float32, or None when it has none on the point, face or corner
    domain."""
    if not has_free_normals(mesh):
        return None
    attribute = mesh.attributes[CUSTOM_NORMAL_ATTRIBUTE]
    if attribute.domain not in ('POINT', 'FACE', 'CORNER'):
        return None
    values = np.empty(len(attribute.data) * 3, dtype=np.float32)
    attribute.data.foreach_get("vector", values)
    values = values.reshape(-1, 3)
    if attribute.domain == 'POINT':
        corner_vertices = np.empty(len(mesh.loops), dtype=np.int32)
        mesh.loops.foreach_get("vertex_index", corner_vertices)
        return values[corner_vertices]
    if attribute.domain == 'FACE':  # faces hold their corners in order (offsets) from 4.0 on
        sizes = np.empty(len(mesh.polygons), dtype=np.int32)
        mesh.polygons.foreach_get("loop_total", sizes)
        return np.repeat(values, sizes, axis=0)
    return values


def set_custom_normals(mesh, normals, vertex_normals=None, free=False):
    """Custom normals: one per corner, normals (L, 3), or, when every corner of a vertex has the same one,
    vertex_normals (V, 3) (normals may then be None).

    In tangent space (every version; normals_split_custom_set and its _from_vertices, which encode each normal in
    its corner's normal space, and take one per vertex several times faster): a zero vector keeps Blender's own
    normal at that corner. Up to 4.0 they show only with Auto Smooth, which this turns on; a mesh that had it off
    gets the widest angle, so that only marked sharp edges (and the normals themselves) split the shading. Blender
    marks the edges sharp where the normals of one smooth fan differ (across creases).

    free (HAS_FREE_NORMALS, 4.5+): the normals (unit vectors) go as they are into the float vector attribute
    "custom_normal", on the point domain (vertex_normals) or the corner domain: free normals, which Blender shades
    with as they are (flat faces and marked sharp edges do not change them), and which cost a copy of the array, or
    nothing where they are the attribute's own (free_vertex_normal_array; the cage's own free normals are carried
    over so, and the limit normals go so where the version has them). Otherwise
    a free "custom_normal" the mesh has goes first: normals_split_custom_set leaves a mesh with free normals
    unchanged (4.5.15, 5.0.1, 5.2.3)."""
    existing = mesh.attributes.get(CUSTOM_NORMAL_ATTRIBUTE) if NAMES_SEAMS_AND_NORMALS else None
    if free:
        domain = 'POINT' if vertex_normals is not None else 'CORNER'
        values = vertex_normals if vertex_normals is not None else normals
        if existing is not None and (existing.data_type, existing.domain) != ('FLOAT_VECTOR', domain):
            mesh.attributes.remove(existing)
            existing = None
        if existing is None:
            existing = mesh.attributes.new(CUSTOM_NORMAL_ATTRIBUTE, 'FLOAT_VECTOR', domain)
        values = np.ascontiguousarray(values, dtype=np.float32).ravel()
        if not memory_views.holds(existing, values):
            existing.data.foreach_set("vector", values)
        return
    if existing is not None and existing.data_type == 'FLOAT_VECTOR':
        mesh.attributes.remove(existing)
    shade_sharp_edges(mesh)
    if vertex_normals is not None:
        mesh.normals_split_custom_set_from_vertices(np.ascontiguousarray(vertex_normals, dtype=np.float32))
    else:
        mesh.normals_split_custom_set(np.ascontiguousarray(normals, dtype=np.float32).reshape(-1, 3))


# Blender 4.1 dropped Auto Smooth. Opening a file saved before 4.1, it appends a Geometry Nodes modifier "Auto Smooth"
# (running a node group of its own making, shared by all) to every mesh object whose mesh had Auto Smooth on and no
# custom normals (BKE_main_mesh_legacy_convert_auto_smooth): to an entry's owner after the entry, and to the entry's
# hidden helper when the result saved had Blender's own normals (the helper's mesh took the cage's Auto Smooth, or
# Auto Smooth at 180 degrees). Seen in 4.2.23, 4.5.15, 5.0.1 and 5.2.3 on a file saved by 3.4.1.
_AUTO_SMOOTH_NODES = sorted((
    "NodeGroupOutput", "NodeGroupInput", "NodeGroupInput", "GeometryNodeSetShadeSmooth", "GeometryNodeSetShadeSmooth",
    "GeometryNodeInputMeshEdgeAngle", "GeometryNodeInputEdgeSmooth", "GeometryNodeInputShadeSmooth",
    "FunctionNodeBooleanMath", "FunctionNodeCompare"))


def converted_auto_smooth():
    """Whether the file just opened had its Auto Smooth converted to modifiers: saved before 4.1, open in 4.1+."""
    return bpy.app.version >= (4, 1, 0) and tuple(bpy.data.version) < (4, 1, 0)


def auto_smooth_modifiers(obj):
    """The modifiers of obj that run the node group Blender 4.1+ makes when it converts Auto Smooth on loading a file
    (recognised by its nodes, as Blender's own is_auto_smooth_node_tree does; the "Smooth by Angle" asset that Shade
    Auto Smooth adds is another group). Empty before 4.1."""
    if bpy.app.version < (4, 1, 0):
        return []
    return [modifier for modifier in obj.modifiers
            if modifier.type == 'NODES' and modifier.node_group is not None
            and sorted(node.bl_idname for node in modifier.node_group.nodes) == _AUTO_SMOOTH_NODES]
