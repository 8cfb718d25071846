"""From a Blender mesh to its subdivision: the cage and everything a subdivision reads (cage), the refinement of
plans and tessellations (refinement), the result mesh (result), its normals (normals), the tags (tags) and Adaptive
Subdivision's cut (adaptive)."""
