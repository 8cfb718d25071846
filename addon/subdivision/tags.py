"""The tags the rules derive from crease weights, written as attributes: "loop_crease" on edges and
"loop_vertex_type" on points (Refresh Tags on a cage; every result from the plan that made it).
"""
import dataclasses

import numpy as np

from ..blender.mesh_arrays import CREASE_TAG, VERTEX_TYPE_TAG, add_attribute
from ..model import geometry
from ..native import LoopSubError
from .cage import Cage, cone_group_index, cone_vertices, explain, read_vertex_groups


def _classifying(options):
    """Options for a plan that only classifies vertices: the limit surface plays no part in it."""
    return dataclasses.replace(options, use_limit_surface=False)


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


def write_plan_tags(mesh, plan, num_edges):
    """The tags of a result built from plan.output_edges(), from the plan that made it: the classes its vertices take
    at the next level and the edges its rules treat as sharp (tagged creases that pass them, boundary and
    non-manifold edges). No second classification: refining the result further uses exactly these."""
    sharp = np.zeros(num_edges, dtype=bool)
    sharp[plan.sharp_edge_indices] = True
    _replace_tags(mesh, sharp, np.asarray(plan.level_vertex_types(plan.levels), dtype=np.int32))


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
        add_attribute(mesh, name, domain, data_type, values)


def tag_object(obj, options):
    """The Refresh Tags operator's work on one object (its own mesh, in place)."""
    if obj.data.is_editmode:
        raise LoopSubError(f"{obj.name} is in Edit Mode")
    cage = Cage(obj.data)
    cage.validate(obj.name)
    cone_index = cone_group_index(obj, options)
    weights = read_vertex_groups(obj.data, cone_index + 1) if cone_index is not None else None
    try:
        write_tags(obj.data, cage, options, cone_vertices(weights, cone_index))
    except LoopSubError as error:
        raise explain(error, obj.name, cage) from error
