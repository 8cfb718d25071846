// The Tessellation object of the module: the limit surface at a rate per edge (loopsub/tessellation.h).
#pragma once

#include <pybind11/pybind11.h>

namespace loopsub::python {

void bind_tessellation(pybind11::module_& m);

}  // namespace loopsub::python
