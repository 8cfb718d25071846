// The Python module `_loopsub`: numpy in, numpy out, no copies, the GIL released while the core runs. Its parts:
// arguments.h checks the arrays handed in, plan.h binds the Plan and its options, subdivide.h the one-shot call and
// its welding of per-corner values, read_obj.h the command line's OBJ reader; here are the module itself, its errors
// and its constants.
//
// Conventions, so that Blender (and anyone else) gets errors instead of silent conversions:
//   * every input array must already be a numpy array of exactly the right dtype (float32 / int32), C-contiguous,
//     aligned and of the right shape; it is then read in place. A wrong dtype raises TypeError, a wrong shape or
//     layout ValueError, each naming the argument, what was expected and what was given;
//   * loopsub::InputError becomes InputError, a ValueError with its problem's attributes (problems.h),
//     loopsub::MemoryLimitError becomes MemoryError (with the size);
//   * arrays handed out by a Plan are read-only views of the plan's own memory whose base is the Plan object, so
//     the plan lives as long as any of them does.
#include <pybind11/pybind11.h>

#include <exception>
#include <string>

#include "loopsub/loopsub.h"
#include "plan.h"
#include "problems.h"
#include "read_obj.h"
#include "subdivide.h"
#include "tessellation.h"

namespace py = pybind11;

namespace {

void translate_exception(std::exception_ptr p) {
    try {
        if (p) std::rethrow_exception(p);
    } catch (const loopsub::MemoryLimitError& e) {
        // The message must say how much: the core's usually does; otherwise it is added. The exception also
        // carries the number as `required_bytes`, for callers that want to offer a lower level.
        std::string msg = e.what();
        if (msg.find(std::to_string(e.required_bytes)) == std::string::npos)
            msg += " (requires " + loopsub::describe_bytes(e.required_bytes) + ")";
        py::object exc = py::reinterpret_steal<py::object>(PyObject_CallFunction(PyExc_MemoryError, "s", msg.c_str()));
        if (!exc) return;  // PyObject_CallFunction set its own error
        exc.attr("required_bytes") = e.required_bytes;
        PyErr_SetObject(PyExc_MemoryError, exc.ptr());
    } catch (const loopsub::InputError& e) { loopsub::python::set_input_error(e); }
}

constexpr const char* kModuleDoc = R"doc(Loop subdivision of triangle meshes with creases.

Two rule sets: ``"hoppe94"`` (the GDC'99 seed's rules after Hoppe et al. 94: smooth, dart,
regular and irregular crease, corner and cone vertices) and ``"opensubdiv"`` (OpenSubdiv's Loop
scheme: semi-sharp creases, vertex sharpness, Chaikin creasing, both boundary modes).

Arrays are numpy arrays used in place, never converted: vertex data is ``float32``, indices are
``int32``, every array C-contiguous. A wrong dtype raises ``TypeError``; a wrong shape or layout,
invalid mesh or tag (index out of range, degenerate triangle, non-finite value, negative levels)
raises ``ValueError`` (the core's refusals: its subclass ``InputError``, which says where as attributes;
``diagnose`` lists every problem at once); a refinement past ``memory_limit_bytes`` raises ``MemoryError`` whose
``required_bytes`` attribute says how much it would need. The GIL is released while the native
code runs.

Example
-------
>>> import numpy as np, _loopsub
>>> positions = np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], np.float32)
>>> triangles = np.array([[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]], np.int32)
>>> result = _loopsub.subdivide(positions, triangles, levels=2)
>>> result["positions"].shape, result["triangles"].shape
((34, 3), (64, 3))
>>> plan = _loopsub.Plan(triangles, len(positions), levels=2)
>>> moved = plan.evaluate(positions * 2)     # new positions, same topology: no topology work
)doc";

}  // namespace

PYBIND11_MODULE(_loopsub, m) {
    m.doc() = kModuleDoc;
    // pybind11's generated signatures would name the array arguments "handle": each docstring starts with a
    // hand-written signature instead, as numpy's own functions do.
    py::options options;
    options.disable_function_signatures();
    py::register_exception_translator(translate_exception);

    loopsub::python::bind_problems(m);
    loopsub::python::bind_plan(m);
    loopsub::python::bind_subdivide(m);
    loopsub::python::bind_tessellation(m);
    loopsub::python::bind_obj(m);

    m.def(
        "best_kernel", [] { return loopsub::kernel_name(loopsub::best_kernel()); },
        "best_kernel()\n\nName of the widest evaluation kernel this CPU runs ('avx2', 'sse4.1' or 'scalar').");

    m.def(
        "estimate_plan_bytes",
        [](int num_vertices, int num_triangles, int levels, int num_channels, std::int64_t num_edges) {
            if (num_vertices < 0 || num_triangles < 0 || levels < 0 || num_channels < 1)
                throw py::value_error("estimate_plan_bytes: counts must not be negative and num_channels at least 1");
            return loopsub::Plan::estimate_bytes(num_vertices, num_triangles, levels, num_channels, num_edges);
        },
        py::arg("num_vertices"), py::arg("num_triangles"), py::arg("levels"), py::arg("num_channels") = 3,
        py::arg("num_edges") = -1,
        "estimate_plan_bytes(num_vertices, num_triangles, levels, num_channels=3, num_edges=-1)\n\nBytes a plan of "
        "this input and one evaluation of num_channels floats per vertex would hold: the estimate the memory check "
        "compares with memory_limit_bytes (MemoryError.required_bytes, for 3 channels). num_edges < 0: unknown, a "
        "closed mesh's count (3/2 per triangle) stands in.");

    // Index = the uint8 value of Plan.level_vertex_types() (loopsub::VertexType).
    m.attr("VERTEX_TYPES") = py::make_tuple("smooth", "dart", "regular_crease", "irregular_crease", "corner", "cone");
    m.attr("INFINITE_SHARPNESS") = loopsub::kInfiniteSharpness;
}
