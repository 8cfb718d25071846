// The core's input problems in Python: the InputProblem class, the exception InputError (a ValueError) that carries
// one, and diagnose().
#pragma once

#include <pybind11/pybind11.h>

#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::python {

namespace py = pybind11;

// Sets Python's error to an InputError of `error`'s message, with its problem's attributes (all None without one).
void set_input_error(const loopsub::InputError& error);

// Problems (a plan's notes) as Python objects, as diagnose() lists them.
py::list notes_of(const std::vector<loopsub::InputProblem>& notes);

// Registers InputError and diagnose().
void bind_problems(py::module_& m);

}  // namespace loopsub::python
