"""The result's normals: the cage's custom normals carried over, or the limit normals as custom normals, written the
cheapest way each Blender version offers (shading.set_custom_normals; docs/addon.md, Normals).
"""
import numpy as np

from ..blender import shading
from ..model import geometry


class BlenderCorners:
    """The result's corners that keep Blender's own normal with the limit normals: those of flat faces (children of
    the cage's flat-shaded faces: flat, as Subdivision Surface keeps them with Use Limit Surface on), flat (T_out,)
    bool per triangle or None; and those at vertices on marked sharp edges, where the mesh shades with them (Auto
    Smooth up to 4.0), so that a marked sharp edge still shows as one, on_sharp (T_out, 3) bool or None."""

    def __init__(self, flat, on_sharp):
        self.flat = flat
        self.on_sharp = on_sharp

    def corners(self):
        """(T_out, 3) bool: every corner that keeps Blender's own normal."""
        if self.flat is None:
            return self.on_sharp
        flat = np.repeat(self.flat[:, None], 3, axis=1)
        return flat if self.on_sharp is None else flat | self.on_sharp


def blender_normal_corners(source, output, new_edges, sharp, parents):
    """The result's BlenderCorners with the limit normals, None where there are none (or no limit normals). parents:
    each triangle's cage face (result.build_mesh's, None where every cage face is smooth)."""
    if not source.limit_normals:
        return None
    on_sharp = None
    if sharp is not None and sharp.any() and shading.shades_sharp_edges(source.mesh):
        vertices_on_sharp = np.zeros(output.num_vertices, dtype=bool)
        vertices_on_sharp[new_edges[sharp].ravel()] = True
        on_sharp = vertices_on_sharp[output.triangles]
    flat = None if source.smooth.all() else ~source.smooth[parents]
    flat = flat if flat is not None and flat.any() else None
    return None if flat is None and on_sharp is None else BlenderCorners(flat, on_sharp)


def vertex_normal_destination(new, source, output):
    """The array write_limit_normals' cheapest case writes, for the core to evaluate into: where the limit normals
    become free normals one per vertex (4.5+, no corner keeping Blender's own normal (source.blender_corners, set
    before), no fan split), the result's new "custom_normal" (shading.free_vertex_normal_array); else None."""
    if source.limit_normals and source.blender_corners is None and output.one_normal_per_vertex():
        return shading.free_vertex_normal_array(new)
    return None


def write_normals(new, source, refined, blender_corners):
    """Custom normals: the cage's own as it shades with them, interpolated linearly per face (normalised), where it
    shades with them: free normals per corner where the version has them (4.5+), whichever way the cage keeps its
    own (tangent space cost Blender 1.5 s an update at 730,000 corners in 5.3; docs/benchmark.md); else, with the
    limit surface, the limit normals (write_limit_normals)."""
    if source.custom_normals:
        normals = np.array(refined.corners[:, :, source.corners.columns["normal"]], dtype=np.float32)
        geometry.normalize(normals)
        if shading.HAS_FREE_NORMALS:
            shading.set_custom_normals(new, normals, free=True)
        else:
            shading.set_custom_normals(new, normals,
                                      geometry.shared_vertex_normals(refined.triangles, normals, len(new.vertices)))
    elif source.limit_normals:
        write_limit_normals(new, refined, refined.vertex[:, source.vertex.columns["position"]], blender_corners)


def write_limit_normals(new, refined, positions, blender_corners):
    """The limit normals of refined (refinement.Refined; the result's positions) as custom normals, but Blender's own at
    blender_corners (a BlenderCorners, or None). Free normals where the version has them (shading.HAS_FREE_NORMALS),
    which Blender shades with as they are: there a flat face's corners get its face normal, worked out here (Blender's
    own, Mesh.polygon_normals, follows the free normals of the update before in 4.5.15), and a corner on a marked
    sharp edge the split normal Blender gives it of itself (shading.own_corner_normals; in tangent space, a zero vector
    there, Blender took 290 ms an update for 147,000 corners in 5.3). Before 4.5 tangent-space normals, a zero vector
    at those corners. One normal per vertex where no side splits a fan and no corner keeps Blender's normal (from
    vertices, tangent space would give a marked sharp edge's sides one normal)."""
    if blender_corners is not None and blender_corners.corners().all():
        return  # every face flat: Blender's own normals are the face normals
    free = shading.HAS_FREE_NORMALS
    vertex_normals = refined.vertex_normals() if blender_corners is None else None
    if vertex_normals is not None:
        shading.set_custom_normals(new, None, vertex_normals, free=free)
        return
    normals = refined.corner_normals()
    if blender_corners is not None:
        if not free:
            normals[blender_corners.corners()] = 0.0
        else:
            on_sharp, flat = blender_corners.on_sharp, blender_corners.flat
            if on_sharp is not None:
                normals[on_sharp] = shading.own_corner_normals(new).reshape(normals.shape)[on_sharp]
            if flat is not None:
                normals[flat] = geometry.triangle_normals(positions, refined.triangles[flat])[:, None, :]
    shading.set_custom_normals(new, normals, free=free)
