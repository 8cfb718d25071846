"""Blender access: every read and write of Blender's data (mesh arrays, creases, normals and shading, the node group
and the modifier stack, the interface's hooks), each version difference once, in the module of its concern; views of
Blender's memory in memory_views alone."""
