"""The result's normals: the cage's custom normals carried over, or the limit normals as custom split normals; or,
for the viewport while it changes, Blender's own normals split where the limit normals split.
"""
import numpy as np

from . import compat, geometry, native


def blender_normal_corners(source, plan, new_edges, sharp, parents):
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


def mark_limit_splits(new, source, plan, sharp):
    """Blender's normals in place of the limit normals (the viewport): the edges across which the limit normals split
    are marked sharp, beside the cage's marked sharp edges, and shade so (Auto Smooth on, at 180 degrees when the cage
    had it off); where nothing splits, the mesh shades smooth with Blender's vertex normals, and Auto Smooth stays as
    the cage had it.

    Where the limit normals split depends on the plan alone (the sides of crease, corner and boundary vertices), not
    on the positions: the plan says which edges (Plan.limit_normal_split_edges, in Plan.output_edges' numbering, as
    the result's edges are), so that even a flat crease, whose sides have one normal, is marked."""
    split = native.run(plan.limit_normal_split_edges)
    if not split.any():
        return
    marked = split if sharp is None else split | sharp
    new.edges.foreach_set("use_edge_sharp", marked)
    compat.shade_sharp_edges(new)


def write_normals(new, source, refined, auto_loops):
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
    """The limit normals (T_out, 3, 3) as custom split normals, but Blender's own at auto_loops (see
    blender_normal_corners). Also what the live entry writes into a result that showed Blender's normals, once it is
    still (live.py)."""
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
