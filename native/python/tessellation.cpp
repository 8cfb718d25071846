#include "tessellation.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <memory>
#include <string>
#include <mutex>
#include <utility>

#include "arguments.h"
#include "loopsub/tessellation.h"
#include "plan.h"
#include "problems.h"

namespace loopsub::python {

namespace {

struct PyTessellation {
    PyTessellation(loopsub::Tessellation&& t, int vertices, std::vector<int> values)
        : tessellation(std::move(t)), num_input_vertices(vertices), layer_values(std::move(values)) {}
    loopsub::Tessellation tessellation;
    int num_input_vertices;
    std::vector<int> layer_values;  // values of each face-varying layer
    std::mutex evaluate_mutex;      // Tessellation::evaluate is not reentrant and runs without the GIL
};

std::unique_ptr<PyTessellation> build(py::handle triangles, long long num_vertices, int rate, py::handle edges,
                                      py::handle edge_rates, py::handle reuse, const OptionArgs& args) {
    PlanInput in;
    read_input(in, triangles, num_vertices, 0, args);
    loopsub::TessellationRates rates;
    rates.uniform_rate = rate;
    py::array edge_array, rate_array;
    if (edges.is_none() != edge_rates.is_none())
        throw py::value_error("edges and edge_rates go together: give both or neither");
    if (!edges.is_none()) {
        edge_array = require_array<std::int32_t>(edges, "edges", {{-1, "K"}, {2, "2"}});
        rate_array = require_array<std::int32_t>(edge_rates, "edge_rates", {{edge_array.shape(0), "K"}});
        rates.edges = data_of<std::int32_t>(edge_array), rates.rates = data_of<std::int32_t>(rate_array);
        rates.num_edges = checked_count(edge_array.shape(0), "number of edges");
    }
    std::vector<int> layer_values;
    for (const loopsub::FaceVaryingLayer& layer : in.layers) layer_values.push_back(layer.num_values);
    loopsub::InputTopology kept;
    if (!reuse.is_none()) {
        if (!py::isinstance<loopsub::InputTopology>(reuse))
            throw py::type_error("reuse must be an InputTopology (Tessellation.input_topology) or None");
        kept = reuse.cast<const loopsub::InputTopology&>();
    }
    py::gil_scoped_release nogil;
    return std::make_unique<PyTessellation>(loopsub::Tessellation(in.mesh, in.options, rates, kept),
                                            in.mesh.num_vertices, std::move(layer_values));
}

py::array face_varying_at_face_points(py::object self, py::handle values, int layer, py::handle out) {
    PyTessellation& p = self.cast<PyTessellation&>();
    const loopsub::Tessellation& t = p.tessellation;
    if (layer < 0 || layer >= int(p.layer_values.size()))
        throw py::index_error("layer must be in [0, " + std::to_string(p.layer_values.size()) + "), got " +
                              std::to_string(layer));
    py::array in = require_array<float>(values, "values", {{p.layer_values[std::size_t(layer)], "V"}, {-1, "C"}});
    const int channels = checked_count(in.shape(1), "number of channels");
    if (channels < 1) throw py::value_error("values need at least one channel");
    py::array result = output_array(out, {{t.num_face_points(), "num_face_points"}, {channels, "C"}}, in);
    const float* src = data_of<float>(in);
    float* dst = static_cast<float*>(result.mutable_data());
    {
        py::gil_scoped_release nogil;
        std::lock_guard<std::mutex> lock(p.evaluate_mutex);
        t.evaluate_face_varying(layer, src, channels, dst);
    }
    return result;
}

py::tuple evaluate_points(py::object self, py::handle positions, py::handle out, py::handle normals_out) {
    PyTessellation& p = self.cast<PyTessellation&>();
    const loopsub::Tessellation& t = p.tessellation;
    py::array in = require_array<float>(positions, "positions", {{p.num_input_vertices, "N"}, {3, "3"}});
    py::array points = output_array(out, {{t.num_points(), "num_points"}, {3, "3"}}, in);
    py::array normals = output_array(normals_out, {{t.num_face_points(), "num_face_points"}, {3, "3"}}, in);
    if (overlaps(normals, points)) throw py::value_error("normals must not share memory with out");
    const float* src = data_of<float>(in);
    float *dst = static_cast<float*>(points.mutable_data()), *n = static_cast<float*>(normals.mutable_data());
    {
        py::gil_scoped_release nogil;
        std::lock_guard<std::mutex> lock(p.evaluate_mutex);
        t.evaluate(src, dst, n);
    }
    return py::make_tuple(points, normals);
}

constexpr const char* kDoc =
    R"doc(Tessellation(triangles, num_vertices, rate=1, *, edges=None, edge_rates=None, reuse=None, uv_interpolation="corners", face_varying_indices=None, rules="hoppe94", crease_edges=None, crease_sharpness=None, corner_vertices=None, corner_sharpness=None, cone_vertices=None, crease_threshold=0.0, boundary="edges", crease_method="uniform", threads=1, scalar=False, memory_limit_bytes=4294967296)

The limit surface at a rate per edge: each triangle cut into a lattice as fine along each edge as
its rate says (``rate`` segments, or the rate ``edge_rates[k]`` of ``edges[k]``, a vertex pair
in either order), every point on the limit surface, the points on the mesh's edges shared by the
triangles on both sides. A triangle's inner rate is the largest of its edges'. A rate of 2**L
gives the vertices of ``Plan(levels=L, limit_surface=True)``. The options are Plan's (the mesh's
tags and the rules); ``evaluate`` places the points for new positions without topology work.

Parameters
----------
triangles : numpy.ndarray of int32, shape (M, 3)
num_vertices : int
rate : int, 1 to 4096
edges : numpy.ndarray of int32, shape (K, 2), optional
edge_rates : numpy.ndarray of int32, shape (K,), optional
reuse : InputTopology, optional
    ``input_topology`` of a tessellation of the same mesh at other rates (a camera's last): what
    depends on the mesh alone is taken from it where its triangles, tags and rules are these,
    else made anew; the result is the same either way.

Face-varying layers (``face_varying_indices``, as Plan's) are refined by ``uv_interpolation``:
``evaluate_face_varying`` gives their values at every face point.

With boundary="none" the triangles a Plan leaves out (the faces at an untagged boundary edge's
ends) shape the surface around them but get no triangles or face points; an input vertex of none
but them keeps its number and its input position.

Raises ``ValueError`` for a rate out of range, an edge no triangle has, and as Plan for a bad
mesh or layer.
)doc";

constexpr const char* kEvaluateDoc = R"doc(evaluate(positions, out=None, normals=None)

positions (N, 3) float32. Returns (points, normals): points (num_points, 3) float32 on the limit
surface, and the unit normal at each face point, (num_face_points, 3) float32 (zero where the
surface has no tangent plane). ``out`` and ``normals`` may be given to be written in place.
)doc";

constexpr const char* kEvaluateLayerDoc = R"doc(evaluate_face_varying(values, layer=0, out=None)

values (V, C) float32, one row per value of face-varying layer ``layer``. Returns (num_face_points,
C) float32: the layer at every face point (per output corner: ``out[corner_face_points]``), refined
by ``uv_interpolation`` as Plan refines it: the layer as a mesh of its own, one vertex per (vertex,
value) pair, cut by the same rates; with "all", linear in each triangle.
)doc";

constexpr const char* kScreenRatesDoc =
    R"doc(screen_space_rates(positions, triangles, world_to_clip, viewport, pixels=1.0, max_rate=64, measure="length", offscreen_scale=4.0)

Rates from a camera, measured as Cycles measures its dicing (as if each edge faced the camera
straight ahead at its midpoint's distance from it): each edge of the mesh cut into as few segments as keep it to ``pixels``
- its length per segment (``measure="length"``, Cycles' dicing rate), or how far a segment may
stray from the surface along the edge, from its bulge after one split (``measure="deviation"``;
then no edge coarser than the other edges of its triangles) - from 1 to ``max_rate``; an edge
out of view (the box around its ends on screen misses it) ``offscreen_scale`` times fewer, one with both ends behind the camera 1.

positions (N, 3) float32, triangles (M, 3) int32, world_to_clip (4, 4) float32 (clip = M (x, y, z,
1), OpenGL's convention: in view where w > 0 and -w <= x, y <= w), viewport (width, height) in
pixels. Returns (edges (E, 2) int32, rates (E,) int32): every edge of the mesh once, for
``Tessellation(..., edges=edges, edge_rates=rates)``.
)doc";

py::tuple screen_rates(py::handle positions, py::handle triangles, py::handle world_to_clip, py::handle viewport,
                       double pixels, int max_rate, const std::string& measure, double offscreen_scale) {
    const auto by = parse_name<loopsub::DicingMeasure>("measure", measure);
    py::array tris = require_array<std::int32_t>(triangles, "triangles", {{-1, "M"}, {3, "3"}});
    py::array points = require_array<float>(positions, "positions", {{-1, "N"}, {3, "3"}});
    py::array matrix = require_array<float>(world_to_clip, "world_to_clip", {{4, "4"}, {4, "4"}});
    const auto size = viewport.cast<std::pair<double, double>>();
    loopsub::MeshView mesh;
    mesh.num_vertices = checked_count(points.shape(0), "number of vertices");
    mesh.triangles = data_of<std::int32_t>(tris);
    mesh.num_triangles = checked_count(tris.shape(0), "number of triangles");
    loopsub::Camera camera;
    std::copy_n(data_of<float>(matrix), 16, camera.world_to_clip);
    camera.viewport_width = float(size.first), camera.viewport_height = float(size.second);
    loopsub::ScreenRates rates;
    {
        py::gil_scoped_release nogil;
        rates = loopsub::screen_space_rates(mesh, data_of<float>(points), camera, float(pixels), max_rate, by,
                                            float(offscreen_scale));
    }
    return py::make_tuple(rows(rates.edges, 2), rows(rates.rates));
}

py::tuple output_edges(PyTessellation& p) {
    loopsub::Tessellation::Edges edges;
    {
        py::gil_scoped_release nogil;
        edges = p.tessellation.output_edges();
    }
    return py::make_tuple(rows(edges.edge_vertices, 2), rows(edges.triangle_edges, 3));
}

using TessellationClass = py::class_<PyTessellation>;

// Construction from the mesh, its rates and options (and an earlier cut's input topology).
void bind_construction(TessellationClass& tessellation) {
    tessellation.def(
        py::init([](py::handle triangles, long long num_vertices, int rate, py::handle edges, py::handle edge_rates,
                    py::object reuse, const std::string& uv_interpolation,
                    py::object face_varying_indices LOOPSUB_FOR_EACH_MESH_OPTION(LOOPSUB_OPTION_PARAMETER)) {
            OptionArgs args;
#define LOOPSUB_OPTION_ASSIGN(type, keyword, default_value) args.keyword = keyword;
            LOOPSUB_FOR_EACH_MESH_OPTION(LOOPSUB_OPTION_ASSIGN)
#undef LOOPSUB_OPTION_ASSIGN
            args.uv_interpolation = uv_interpolation;
            args.face_varying_indices = face_varying_indices;
            return build(triangles, num_vertices, rate, edges, edge_rates, reuse, args);
        }),
        py::arg("triangles"), py::arg("num_vertices"), py::arg("rate") = 1, py::kw_only(),
        py::arg("edges") = py::none(), py::arg("edge_rates") = py::none(), py::arg("reuse") = py::none(),
        py::arg("uv_interpolation") = OptionArgs{}.uv_interpolation,
        py::arg("face_varying_indices") = py::none() LOOPSUB_FOR_EACH_MESH_OPTION(LOOPSUB_OPTION_ARG));
}

// The frame: the points and normals for new positions, a face-varying layer's values at the face points.
void bind_evaluation(TessellationClass& tessellation) {
    tessellation
        .def("evaluate", &evaluate_points, kEvaluateDoc, py::arg("positions"), py::arg("out") = py::none(),
             py::arg("normals") = py::none())
        .def("evaluate_face_varying", &face_varying_at_face_points, kEvaluateLayerDoc, py::arg("values"),
             py::arg("layer") = 0, py::arg("out") = py::none())
        .def_property_readonly(
            "num_face_varying_layers", [](PyTessellation& p) { return int(p.layer_values.size()); },
            "int: the face-varying layers given.");
}

// The result: its counts, its triangles and face points (read-only views of its memory) and its edges.
void bind_result(TessellationClass& tessellation) {
    tessellation
        .def_property_readonly(
            "num_points", [](PyTessellation& p) { return p.tessellation.num_points(); }, "int: points of the result.")
        .def_property_readonly(
            "num_face_points", [](PyTessellation& p) { return p.tessellation.num_face_points(); },
            "int: points of each input triangle, counted per triangle (the normals' rows).")
        .def_property_readonly(
            "levels", [](PyTessellation& p) { return p.tessellation.levels(); },
            "int: the refinement levels the points are made from.")
        .def_property_readonly(
            "input_topology", [](PyTessellation& p) { return p.tessellation.input_topology(); },
            "InputTopology: what this read of its input mesh alone, for Tessellation(..., reuse=) at other rates.")
        .def_property_readonly(
            "estimated_bytes", [](PyTessellation& p) { return p.tessellation.estimated_bytes(); },
            "int: bytes the memory check counted against memory_limit_bytes: the result's arrays, the plans of the "
            "input triangles that are no patch, each UV layer's own cut.")
        .def_property_readonly(
            "notes", [](PyTessellation& p) { return notes_of(p.tessellation.notes()); },
            "list: what the core's checks found to tell of the input that is no error, as Plan.notes (each edge two "
            "triangles run along the same way).")
        .def_property_readonly(
            "triangles",
            [](py::object self) {
                const auto& t = self.cast<PyTessellation&>().tessellation;
                return plan_view(t.triangles(), {t.num_triangles(), 3}, self);
            },
            "(T, 3) int32: the result's triangles, counter-clockwise (read-only view).")
        .def_property_readonly(
            "parent_triangles",
            [](py::object self) {
                const auto& t = self.cast<PyTessellation&>().tessellation;
                return plan_view(t.parent_triangles(), {t.num_triangles()}, self);
            },
            "(T,) int32: the input triangle each triangle lies in (read-only view).")
        .def_property_readonly(
            "corner_face_points",
            [](py::object self) {
                const auto& t = self.cast<PyTessellation&>().tessellation;
                return plan_view(t.corner_face_points(), {t.num_triangles(), 3}, self);
            },
            "(T, 3) int32: each corner's face point, the row of its normal (read-only view).")
        .def_property_readonly(
            "face_point_parameters",
            [](py::object self) {
                const auto& t = self.cast<PyTessellation&>().tessellation;
                return plan_view(t.face_point_parameters(), {t.num_face_points(), 2}, self);
            },
            "(num_face_points, 2) float32: each face point's (u, v) in its triangle, corner 0 + u (corner 1 - "
            "corner 0) + v (corner 2 - corner 0) (read-only view).")
        .def("output_edges", &output_edges,
             "output_edges()\n\n(edge_vertices (E, 2) int32, triangle_edges (T, 3) int32): the triangles' edges, each "
             "once, and each triangle's edges (edge k joins corners k and k + 1), as Plan.output_edges: a mesh "
             "without an edge search. New arrays.");
}

void bind_screen_space_rates(py::module_& m) {
    m.def("screen_space_rates", &screen_rates, kScreenRatesDoc, py::arg("positions"), py::arg("triangles"),
          py::arg("world_to_clip"), py::arg("viewport"), py::arg("pixels") = 1.0, py::arg("max_rate") = 64,
          py::arg("measure") = "length", py::arg("offscreen_scale") = 4.0);
}

}  // namespace

void bind_tessellation(py::module_& m) {
    bind_screen_space_rates(m);
    py::class_<loopsub::InputTopology>(
        m, "InputTopology",
        "What a Tessellation read of its input mesh alone (Tessellation.input_topology), "
        "for one of the same mesh at other rates: Tessellation(..., reuse=). It holds "
        "nothing of the result.");
    TessellationClass tessellation(m, "Tessellation", kDoc);
    bind_construction(tessellation);
    bind_evaluation(tessellation);
    bind_result(tessellation);
}

}  // namespace loopsub::python
