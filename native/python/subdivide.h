// subdivide(), the one-shot call, and weld_corner_values(), the welding of per-corner values it does.
#pragma once

#include <pybind11/pybind11.h>

namespace loopsub::python {

void bind_subdivide(pybind11::module_& m);

}  // namespace loopsub::python
