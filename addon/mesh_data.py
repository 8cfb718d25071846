"""Moving mesh data between Blender and numpy: arrays through foreach_get / foreach_set, and the names of the
attributes the add-on writes. The add-on's mesh work reads the cage (cage.py), builds the result (result.py), writes
its normals (normals.py) and its tags (tags.py) through these.
"""
import numpy as np

from . import geometry

CREASE_TAG = "loop_crease"


VERTEX_TYPE_TAG = "loop_vertex_type"


def read_array(collection, prop, count, width, dtype):
    values = np.empty(count * width, dtype=dtype)
    collection.foreach_get(prop, values)
    return values.reshape(count, width) if width > 1 else values


def read_attribute(attribute, count):
    prop, width, dtype = geometry.ATTRIBUTE_LAYOUT[attribute.data_type]
    return read_array(attribute.data, prop, count, width, dtype).reshape(count, width)


def fill_attribute(attribute, data_type, values):
    attribute.data.foreach_set(geometry.ATTRIBUTE_LAYOUT[data_type][0], np.ascontiguousarray(values).ravel())


def add_attribute(mesh, name, domain, data_type, values):
    attribute = mesh.attributes.new(name, data_type, domain)
    fill_attribute(attribute, data_type, values)
    return attribute
