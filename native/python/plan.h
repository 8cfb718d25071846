// The Plan object of the module: its options, how it is built from Python arguments, and its evaluations, which
// subdivide() calls too.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::python {

namespace py = pybind11;

// The options Plan() and subdivide() both take, keyword-only and in this order, as X(type, keyword, default): the one
// list that the bindings' parameters, their keyword arguments and OptionArgs are made from. Tessellation() takes the
// first part, the mesh's tags and the rules.
#define LOOPSUB_FOR_EACH_OPTION(X) LOOPSUB_FOR_EACH_MESH_OPTION(X) LOOPSUB_FOR_EACH_PLAN_OPTION(X)
#define LOOPSUB_FOR_EACH_MESH_OPTION(X)         \
    X(std::string, rules, "hoppe94")            \
    X(py::object, crease_edges, py::none())     \
    X(py::object, crease_sharpness, py::none()) \
    X(py::object, corner_vertices, py::none())  \
    X(py::object, corner_sharpness, py::none()) \
    X(py::object, cone_vertices, py::none())    \
    X(double, crease_threshold, 0.0)            \
    X(std::string, boundary, "edges")           \
    X(std::string, crease_method, "uniform")    \
    X(int, threads, 1)                          \
    X(bool, scalar, false)                      \
    X(long long, memory_limit_bytes, static_cast<long long>(loopsub::Options{}.memory_limit_bytes))
#define LOOPSUB_FOR_EACH_PLAN_OPTION(X)             \
    X(bool, limit_surface, false)                   \
    X(std::string, uv_interpolation, "corners")     \
    X(py::object, face_varying_indices, py::none()) \
    X(py::object, hole_triangles, py::none())       \
    X(std::string, level_tables, "auto")

// After a binding's own parameters: ", type keyword" for each option.
#define LOOPSUB_OPTION_PARAMETER(type, keyword, default_value) , type keyword
// After its own py::arg()s: ", py::arg(keyword) = default" for each option (following a py::kw_only()).
#define LOOPSUB_OPTION_ARG(type, keyword, default_value) , py::arg(#keyword) = default_value
// In the binding: the OptionArgs of its option parameters.
#define LOOPSUB_OPTION_VALUE(type, keyword, default_value) keyword,

// The options as Python gave them, read by build_plan (those not given: their defaults).
struct OptionArgs {
#define LOOPSUB_OPTION_FIELD(type, keyword, default_value) type keyword = default_value;
    LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_FIELD)
#undef LOOPSUB_OPTION_FIELD
};

struct PyPlan {
    PyPlan(loopsub::Plan&& p, int triangles, std::vector<int> values)
        : plan(std::move(p)), num_input_triangles(triangles), layer_values(std::move(values)) {}
    loopsub::Plan plan;
    int num_input_triangles;        // the core does not keep it; face-varying input is checked against it
    std::vector<int> layer_values;  // values of each face-varying layer
    // Plan::evaluate is not reentrant (it owns scratch buffers) and runs without the GIL, so two Python threads
    // evaluating one plan must take turns.
    std::mutex evaluate_mutex;
};

// Crease edges or corner vertices and their sharpness, as read from Python.
struct SharpTags {
    py::array tags, given_sharpness;
    std::vector<float> default_sharpness;  // when only the tags are given
    int count = 0;
    const std::int32_t* indices = nullptr;
    const float* sharpness = nullptr;
};

// Everything a Plan (or a Tessellation) is built from, read from Python while the GIL is held. The py::array members
// keep the caller's buffers alive (and referenced by `mesh`) while the core runs without the GIL.
struct PlanInput {
    py::array triangles, cone_vertices, holes;
    SharpTags creases, corners;
    std::vector<py::array> layer_arrays;  // face_varying_indices as given, then subdivide()'s welded per-corner values
    std::vector<loopsub::FaceVaryingLayer> layers;
    loopsub::MeshView mesh;
    loopsub::Options options;
};
void read_input(PlanInput& in, py::handle triangles, long long num_vertices, int levels, const OptionArgs& o,
                const std::vector<py::array>& welded_layers = {});

// The plan of Plan(triangles, num_vertices, levels, **options); welded_layers (subdivide()'s per-corner values, as
// (M, 3) int32 value indices) come after the face_varying_indices given.
std::unique_ptr<PyPlan> build_plan(py::handle triangles, long long num_vertices, int levels, const OptionArgs& args,
                                   const std::vector<py::array>& welded_layers = {});

// A read-only numpy view of memory owned by `base` (a Python Plan or Tessellation), which stays alive as long as the
// view.
template <typename T>
py::array plan_view(const T* data, std::vector<py::ssize_t> shape, py::handle base) {
    py::array a(py::dtype::of<T>(), std::move(shape), data, base);
    a.attr("setflags")(py::arg("write") = false);
    return a;
}

// A read-only view of one of the plan's output tag vectors (Plan::output_crease_edges and the like): (K, 2) for vertex
// pairs, else (K,).
template <typename T>
py::array tag_view(py::handle plan, const std::vector<T>& (loopsub::Plan::*tags)() const, bool pairs = false) {
    const std::vector<T>& v = (plan.cast<PyPlan&>().plan.*tags)();
    if (pairs) return plan_view(v.data(), {py::ssize_t(v.size() / 2), 2}, plan);
    return plan_view(v.data(), {py::ssize_t(v.size())}, plan);
}

// Plan.evaluate, Plan.evaluate_with_normals and Plan.evaluate_face_varying(values, out, layer=layer).
py::array evaluate(py::object self, py::handle values, py::handle out);
py::tuple evaluate_with_normals(py::object self, py::handle positions, py::handle out, py::handle normals_out);
py::array evaluate_layer(PyPlan& p, int layer, py::handle values, py::handle out);

// Registers Plan and option_names().
void bind_plan(py::module_& m);

}  // namespace loopsub::python
