#include "subdivide.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "arguments.h"
#include "loopsub/loopsub.h"
#include "plan.h"

namespace loopsub::python {

namespace {

// Per-corner values, (T, 3, C) or (T, 3) and checked, welded into a face-varying layer: its value indices (T, 3) and
// its values, (V, C) or (V,).
std::pair<py::array, py::array> weld_layer(const py::array& triangles, int num_vertices,
                                           const py::array& corner_values) {
    const int num_triangles = int(triangles.shape(0));
    const int channels = corner_values.ndim() == 3 ? int(corner_values.shape(2)) : 1;
    const std::int32_t* corner_vertices = data_of<std::int32_t>(triangles);
    const float* values_in = data_of<float>(corner_values);
    py::array indices = new_array<std::int32_t>({py::ssize_t(num_triangles), py::ssize_t(3)});
    auto* corner_indices = static_cast<std::int32_t*>(indices.mutable_data());
    int num_values = 0;
    {
        py::gil_scoped_release nogil;
        num_values = loopsub::weld_corner_values(corner_indices, corner_vertices, num_triangles, num_vertices,
                                                 values_in, channels);
    }
    std::vector<py::ssize_t> shape{num_values};
    if (corner_values.ndim() == 3) shape.push_back(channels);
    py::array values = new_array<float>(shape);
    float* values_out = static_cast<float*>(values.mutable_data());
    {
        py::gil_scoped_release nogil;
        loopsub::gather_welded_values(values_out, corner_indices, num_triangles, values_in, channels);
    }
    return {indices, values};
}

// vertex_data / face_varying may be one array or a dict of arrays; the result mirrors the argument.
template <typename Eval>
py::object map_data(py::handle data, Eval eval) {
    if (data.is_none()) return py::none();
    if (py::isinstance<py::dict>(data)) {
        py::dict result;
        for (auto item : py::reinterpret_borrow<py::dict>(data)) result[item.first] = eval(item.second);
        return std::move(result);
    }
    return eval(data);
}

// The arrays of vertex_data / face_varying in order, each with its name as a message gives it: "face_varying['uv']".
struct Named {
    py::array array;
    std::string name;
};
std::vector<Named> named_arrays(py::handle data, const char* name) {
    std::vector<Named> arrays;
    if (data.is_none()) return arrays;
    if (py::isinstance<py::dict>(data)) {
        for (auto item : py::reinterpret_borrow<py::dict>(data))
            arrays.push_back({py::reinterpret_borrow<py::array>(item.second),
                              std::string(name) + "[" + std::string(py::repr(item.first)) + "]"});
    } else {
        arrays.push_back({py::reinterpret_borrow<py::array>(data), name});
    }
    return arrays;
}

// Per-corner face-varying arrays welded into layers (numbered from first_layer), each checked first where its value's
// place is still its corner (the core's check; InputError naming the argument). Corners of a vertex with equal values
// (bit for bit, -0.0 and 0.0 alike) share a value.
struct WeldedLayers {
    std::vector<py::array> indices, values;
};
WeldedLayers weld_layers(const std::vector<Named>& corner_arrays, const py::array& tris, int n, int first_layer) {
    const int m = int(tris.shape(0));
    // Only triangles a plan takes are welded: a vertex index out of range is the plan's to refuse, after the options,
    // as without face-varying data; until then a layer of one value holds each layer's place.
    const std::int32_t* corner_vertices = data_of<std::int32_t>(tris);
    const bool plan_takes_them = std::all_of(corner_vertices, corner_vertices + 3 * std::size_t(m),
                                             [n](std::int32_t v) { return v >= 0 && v < n; });
    WeldedLayers welded;
    for (std::size_t k = 0; k < corner_arrays.size(); ++k) {
        const py::array& a = corner_arrays[k].array;
        const int channels = a.ndim() == 3 ? int(a.shape(2)) : 1;
        const std::vector<loopsub::InputProblem> problems =
            loopsub::diagnose_corner_values(data_of<float>(a), m, channels, first_layer + int(k));
        if (!problems.empty()) throw loopsub::InputError(problems[0], corner_arrays[k].name + ": ");
        if (!plan_takes_them) {
            welded.indices.push_back(new_array<std::int32_t>({py::ssize_t(m), py::ssize_t(3)}));
            std::fill_n(static_cast<std::int32_t*>(welded.indices.back().mutable_data()), 3 * std::size_t(m), 0);
            continue;
        }
        auto [indices, values] = weld_layer(tris, n, a);
        welded.indices.push_back(indices);
        welded.values.push_back(values);
    }
    return welded;
}

// A layer refined per value, then spread to the output's corners: (M_out, 3, C) or (M_out, 3).
py::array refine_to_corners(PyPlan& q, int layer, const py::array& layer_values) {
    const py::array values = evaluate_layer(q, layer, layer_values, py::none());
    const std::size_t channels = values.ndim() == 2 ? std::size_t(values.shape(1)) : 1;
    const py::ssize_t t_out = q.plan.num_output_triangles();
    std::vector<py::ssize_t> shape{t_out, 3};
    if (values.ndim() == 2) shape.push_back(py::ssize_t(channels));
    py::array result(py::dtype::of<float>(), shape);
    const std::int32_t* indices = q.plan.output_face_varying_indices(layer);
    const float* src = data_of<float>(values);
    float* dst = static_cast<float*>(result.mutable_data());
    for (py::ssize_t c = 0; c < 3 * t_out; ++c)
        std::copy_n(src + std::size_t(indices[c]) * channels, channels, dst + c * channels);
    return result;
}

// The result dict of a plan: its positions (and normals), connectivity and tags, and the data refined.
py::dict result_of(py::object plan, const py::array& pos, py::handle vertex_data, py::handle face_varying,
                   int first_layer, const WeldedLayers& layers) {
    PyPlan& p = plan.cast<PyPlan&>();
    const py::handle none = py::none();
    const py::ssize_t m_out = p.plan.num_output_triangles();
    py::dict r;
    if (p.plan.options().limit_surface) {
        py::tuple both = evaluate_with_normals(plan, pos, none, none);
        r["positions"] = both[0];
        r["normals"] = both[1];
    } else {
        r["positions"] = evaluate(plan, pos, none);
    }
    r["triangles"] = plan_view(p.plan.output_triangles(), {m_out, 3}, plan);
    r["parent_triangles"] = plan_view(p.plan.output_parent_triangles(), {m_out}, plan);
    r["crease_edges"] = tag_view(plan, &loopsub::Plan::output_crease_edges, true);
    r["crease_sharpness"] = tag_view(plan, &loopsub::Plan::output_crease_sharpness);
    r["corner_vertices"] = tag_view(plan, &loopsub::Plan::output_corner_vertices);
    r["corner_sharpness"] = tag_view(plan, &loopsub::Plan::output_corner_sharpness);
    r["vertex_data"] = map_data(vertex_data, [&](py::handle a) { return evaluate(plan, a, none); });
    std::size_t next = 0;
    r["face_varying"] = map_data(face_varying, [&](py::handle) {
        const int layer = first_layer + int(next);
        return refine_to_corners(p, layer, layers.values[next++]);
    });
    r["plan"] = plan;
    return r;
}

py::dict subdivide(py::handle positions, py::handle triangles, int levels, const OptionArgs& args,
                   py::handle vertex_data, py::handle face_varying) {
    py::array pos = require_array<float>(positions, "positions", {{-1, "N"}, {3, "3"}});
    // Every array is checked before the (possibly long) topology work, so a bad argument fails fast.
    py::array tris = require_array<std::int32_t>(triangles, "triangles", {{-1, "M"}, {3, "3"}});
    const int n = checked_count(pos.shape(0), "number of vertices");
    const int m = checked_count(tris.shape(0), "number of triangles");
    for (const Named& a : named_arrays(vertex_data, "vertex_data")) read_vertex_values(a.array, a.name.c_str(), n);
    const std::vector<Named> corner_arrays = named_arrays(face_varying, "face_varying");
    for (const Named& a : corner_arrays) read_corner_values(a.array, a.name.c_str(), m);

    // Per-corner face-varying arrays become layers after the face_varying_indices given.
    const int first_layer = args.face_varying_indices.is_none() ? 0 : int(py::len(args.face_varying_indices));
    const WeldedLayers layers = weld_layers(corner_arrays, tris, n, first_layer);
    py::object plan = py::cast(build_plan(tris, n, levels, args, layers.indices));
    return result_of(plan, pos, vertex_data, face_varying, first_layer, layers);
}

constexpr const char* kSubdivideDoc =
    R"doc(subdivide(positions, triangles, levels=1, *, <the options of Plan>, vertex_data=None, face_varying=None)

Subdivide a mesh in one call (builds a Plan and evaluates it).

Parameters
----------
positions : numpy.ndarray of float32, shape (N, 3)
triangles : numpy.ndarray of int32, shape (M, 3)
levels : int, optional
    Default 1.
rules, crease_edges, crease_sharpness, corner_vertices, corner_sharpness, cone_vertices, crease_threshold, boundary, crease_method, threads, scalar, memory_limit_bytes, limit_surface, uv_interpolation, face_varying_indices, hole_triangles, level_tables
    As for :class:`Plan`.
vertex_data : numpy.ndarray of float32, shape (N, C) or (N,), or dict of them, optional
    Other per-vertex channels, refined with the same weights as the positions.
face_varying : numpy.ndarray of float32, shape (M, 3, C) or (M, 3), or dict of them, optional
    Per-corner data (UVs), refined by ``uv_interpolation``: the corners of a vertex with equal values
    (bit for bit, -0.0 and 0.0 alike) share one value, different values make a seam there (``weld_corner_values``).

Returns
-------
dict
    ``positions`` (N_out, 3) float32; ``triangles`` (M_out, 3) int32; ``parent_triangles`` (M_out,) int32
    (index of the input triangle each output triangle comes from); ``crease_edges`` (K, 2) int32 and
    ``crease_sharpness`` (K,) float32, ``corner_vertices`` and ``corner_sharpness``: the output's tags, ready
    to be fed back in; ``vertex_data`` and ``face_varying``: refined like the arguments (an array, a dict with the
    same keys, or None; face-varying data per output corner); ``normals`` (M_out, 3, 3) with ``limit_surface``
    (see ``Plan.evaluate_with_normals``); ``plan``: the :class:`Plan`, to re-evaluate new positions on the same
    topology.
    The index and tag arrays are read-only views of the plan's memory.
)doc";

constexpr const char* kWeldDoc = R"doc(weld_corner_values(triangles, num_vertices, corner_values)

Weld per-corner values (a UV map read per triangle corner) into a face-varying layer, as ``subdivide`` does with
its ``face_varying`` data.

Parameters
----------
triangles : numpy.ndarray of int32, shape (M, 3)
num_vertices : int
    Number of vertices; every index in ``triangles`` must be below it.
corner_values : numpy.ndarray of float32, shape (M, 3, C) or (M, 3)
    The values at each corner of each triangle.

Returns
-------
tuple of numpy.ndarray
    ``(indices, values)``: the value index of each corner (M, 3) int32, as ``Plan``'s ``face_varying_indices``
    takes it, and the values (V, C) or (V,) float32. The corners of a vertex whose values are equal (bit for bit,
    -0.0 and 0.0 alike) share one value; different values make a seam there. Values are numbered vertex by vertex,
    and within a vertex in the order of their first corner, so that the indices change only where corners join or
    leave a value. Each value is that of its first corner.
)doc";

}  // namespace

void bind_subdivide(py::module_& m) {
    m.def(
        "subdivide",
        [](py::handle positions, py::handle triangles, int levels LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_PARAMETER),
           py::handle vertex_data, py::handle face_varying) {
            return subdivide(positions, triangles, levels, OptionArgs{LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_VALUE)},
                             vertex_data, face_varying);
        },
        kSubdivideDoc, py::arg("positions"), py::arg("triangles"), py::arg("levels") = 1,
        py::kw_only() LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_ARG), py::arg("vertex_data") = py::none(),
        py::arg("face_varying") = py::none());

    m.def(
        "weld_corner_values",
        [](py::handle triangles, long long num_vertices, py::handle corner_values) {
            py::array tris = require_array<std::int32_t>(triangles, "triangles", {{-1, "M"}, {3, "3"}});
            const int num_triangles = checked_count(tris.shape(0), "number of triangles");
            const py::array values = read_corner_values(corner_values, "corner_values", num_triangles).first;
            auto [indices, welded] = weld_layer(tris, checked_count(num_vertices, "num_vertices"), values);
            return py::make_tuple(indices, welded);
        },
        kWeldDoc, py::arg("triangles"), py::arg("num_vertices"), py::arg("corner_values"));
}

}  // namespace loopsub::python
