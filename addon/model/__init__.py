"""The add-on's model of a subdivision without Blender: the crease mapping and mesh arithmetic (geometry), the settings
(settings) and the memory estimates (memory). Nothing here imports bpy: tests import it without Blender."""
