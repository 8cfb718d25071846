// read_obj(): the OBJ reader the command line uses (native/obj/), for Python callers that want a file's mesh and
// OpenSubdiv's tags without reading them again (scripts/demo_blender.py).
#pragma once

#include <pybind11/pybind11.h>

namespace loopsub::python {

void bind_obj(pybind11::module_& m);

}  // namespace loopsub::python
