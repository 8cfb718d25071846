#include "plan.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "arguments.h"
#include "problems.h"

namespace loopsub::python {

namespace {

// `tags_arg` (K vertex pairs, or K vertices) and `sharpness_arg` (K values, or None) into `out`.
void read_sharp_tags(py::handle tags_arg, const char* tags_name, bool pairs, py::handle sharpness_arg,
                     const char* sharpness_name, const char* count_name, SharpTags& out) {
    if (tags_arg.is_none()) {
        if (!sharpness_arg.is_none())
            throw py::value_error(std::string(sharpness_name) + " was given without " + tags_name);
        return;
    }
    out.tags = pairs ? require_array<std::int32_t>(tags_arg, tags_name, {{-1, "K"}, {2, "2"}})
                     : require_array<std::int32_t>(tags_arg, tags_name, {{-1, "K"}});
    const py::ssize_t k = out.tags.shape(0);
    out.count = checked_count(k, count_name);
    out.indices = data_of<std::int32_t>(out.tags);
    if (sharpness_arg.is_none()) {
        // Tags without sharpness are infinitely sharp, as OpenSubdiv's SHARPNESS_INFINITE.
        out.default_sharpness.assign(std::size_t(k), loopsub::kInfiniteSharpness);
        out.sharpness = out.default_sharpness.data();
    } else {
        out.given_sharpness = require_array<float>(sharpness_arg, sharpness_name, {{k, "K"}});
        out.sharpness = data_of<float>(out.given_sharpness);
    }
}

}  // namespace

void read_input(PlanInput& in, py::handle triangles, long long num_vertices, int levels, const OptionArgs& o,
                const std::vector<py::array>& welded_layers) {
    // levels and threads are checked by the core, before it starts a thread.
    if (num_vertices < 0) throw py::value_error("num_vertices must be >= 0, got " + std::to_string(num_vertices));
    if (o.memory_limit_bytes < 0)
        throw py::value_error("memory_limit_bytes must be >= 0, got " + std::to_string(o.memory_limit_bytes));
    if (!std::isfinite(o.crease_threshold))
        throw py::value_error("crease_threshold must be finite, got " + std::to_string(o.crease_threshold));

    loopsub::Options& opt = in.options;
    opt.rules = parse_name<loopsub::Rules>("rules", o.rules);
    opt.boundary = parse_name<loopsub::Boundary>("boundary", o.boundary);
    opt.crease_method = parse_name<loopsub::CreaseMethod>("crease_method", o.crease_method);
    opt.levels = levels;
    opt.crease_threshold = float(o.crease_threshold);
    opt.threads = o.threads;
    opt.kernel = o.scalar ? loopsub::Kernel::Scalar : loopsub::Kernel::Auto;
    opt.memory_limit_bytes = std::uint64_t(o.memory_limit_bytes);
    opt.limit_surface = o.limit_surface;
    opt.face_varying = parse_name<loopsub::FaceVaryingInterpolation>("uv_interpolation", o.uv_interpolation);
    opt.level_tables = parse_name<loopsub::LevelTables>("level_tables", o.level_tables);

    loopsub::MeshView& mesh = in.mesh;
    mesh.num_vertices = checked_count(num_vertices, "num_vertices");
    in.triangles = require_array<std::int32_t>(triangles, "triangles", {{-1, "M"}, {3, "3"}});
    mesh.triangles = data_of<std::int32_t>(in.triangles);
    mesh.num_triangles = checked_count(in.triangles.shape(0), "number of triangles");

    read_sharp_tags(o.crease_edges, "crease_edges", true, o.crease_sharpness, "crease_sharpness",
                    "number of crease edges", in.creases);
    mesh.crease_edges = in.creases.indices;
    mesh.crease_sharpness = in.creases.sharpness;
    mesh.num_crease_edges = in.creases.count;
    read_sharp_tags(o.corner_vertices, "corner_vertices", false, o.corner_sharpness, "corner_sharpness",
                    "number of corner vertices", in.corners);
    mesh.corner_vertices = in.corners.indices;
    mesh.corner_sharpness = in.corners.sharpness;
    mesh.num_corners = in.corners.count;

    if (!o.cone_vertices.is_none()) {
        in.cone_vertices = require_array<std::int32_t>(o.cone_vertices, "cone_vertices", {{-1, "Q"}});
        mesh.num_cones = checked_count(in.cone_vertices.shape(0), "number of cone vertices");
        mesh.cone_vertices = data_of<std::int32_t>(in.cone_vertices);
    }
    if (!o.hole_triangles.is_none()) {
        in.holes = require_array<std::int32_t>(o.hole_triangles, "hole_triangles", {{-1, "H"}});
        mesh.num_holes = checked_count(in.holes.shape(0), "number of holes");
        mesh.hole_triangles = data_of<std::int32_t>(in.holes);
    }
    if (!o.face_varying_indices.is_none()) {
        if (!py::isinstance<py::sequence>(o.face_varying_indices) || py::isinstance<py::array>(o.face_varying_indices))
            throw py::type_error("face_varying_indices must be a list of int32 arrays of shape (M, 3), one per layer");
        for (py::handle item : py::reinterpret_borrow<py::sequence>(o.face_varying_indices)) {
            const std::string name = "face_varying_indices[" + std::to_string(in.layer_arrays.size()) + "]";
            in.layer_arrays.push_back(
                require_array<std::int32_t>(item, name.c_str(), {{mesh.num_triangles, "M"}, {3, "3"}}));
        }
    }
    in.layer_arrays.insert(in.layer_arrays.end(), welded_layers.begin(), welded_layers.end());
    for (const py::array& a : in.layer_arrays) {
        // A layer has as many values as its largest index says; evaluate_face_varying wants exactly that many.
        const std::int32_t* indices = data_of<std::int32_t>(a);
        const std::int32_t* largest = std::max_element(indices, indices + 3 * std::size_t(mesh.num_triangles));
        in.layers.push_back(
            {indices, largest == indices + 3 * std::size_t(mesh.num_triangles) ? 0 : std::max(*largest + 1, 0)});
    }
    mesh.face_varying = in.layers.data();
    mesh.num_face_varying = int(in.layers.size());
}

namespace {

// A face-varying layer's index as the caller gave it: any integer (numpy's too; a huge one is out of range, not a
// failed conversion), checked against the plan's layers.
int layer_index(const PyPlan& p, py::handle layer) {
    const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(layer.ptr()));
    if (!index) {
        PyErr_Clear();
        throw py::type_error("layer must be an integer, got " +
                             std::string(py::str(py::type::handle_of(layer).attr("__name__"))));
    }
    int overflow = 0;
    const long long k = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if (overflow != 0 || k < 0 || k >= static_cast<long long>(p.layer_values.size()))
        throw py::value_error("layer " + std::string(py::str(index)) +
                              " is not a face-varying layer of this Plan (it has " +
                              std::to_string(p.layer_values.size()) + ")");
    return int(k);
}

py::array evaluate_face_varying(py::object self, py::handle values, py::handle out, py::object layer) {
    PyPlan& p = self.cast<PyPlan&>();
    if (!layer.is_none()) return evaluate_layer(p, layer_index(p, layer), values, out);
    auto [in, channels] = read_corner_values(values, "values", p.num_input_triangles);
    std::vector<Dim> dims{{p.plan.num_output_triangles(), "T_out"}, {3, "3"}};
    if (in.ndim() == 3) dims.push_back({channels, "C"});
    py::array result = output_array(out, dims, in);
    if (channels == 0) return result;

    const float* src = data_of<float>(in);
    float* dst = static_cast<float*>(result.mutable_data());
    {
        py::gil_scoped_release nogil;
        // The core refuses a non-finite value (InputError, at its triangle and corner): linear interpolation would
        // spread it silently.
        p.plan.evaluate_face_varying(src, dst, channels);  // const: safe next to evaluate()
    }
    return result;
}

constexpr const char* kPlanDoc =
    R"doc(Plan(triangles, num_vertices, levels=1, *, rules="hoppe94", crease_edges=None, crease_sharpness=None, corner_vertices=None, corner_sharpness=None, cone_vertices=None, crease_threshold=0.0, boundary="edges", crease_method="uniform", threads=1, scalar=False, memory_limit_bytes=4294967296, limit_surface=False, uv_interpolation="corners", face_varying_indices=None, hole_triangles=None, level_tables="auto")

The topology work of Loop subdivision, done once for a mesh and reused per frame.

Parameters
----------
triangles : numpy.ndarray of int32, shape (M, 3)
    Vertex indices of each triangle, counter-clockwise. Read during construction only.
num_vertices : int
    Number of vertices N of the input mesh.
levels : int, optional
    Levels of subdivision (default 1); each splits every triangle into four.
rules : {"hoppe94", "opensubdiv"}, optional
    The rule set (default ``"hoppe94"``).
crease_edges : numpy.ndarray of int32, shape (K, 2), optional
    Tagged edges as vertex pairs (either order).
crease_sharpness : numpy.ndarray of float32, shape (K,), optional
    Sharpness of each tagged edge (>= 0; 10 is infinitely sharp). Default: 10 for every tagged edge.
corner_vertices : numpy.ndarray of int32, shape (K,), optional
    Vertices with a corner sharpness.
corner_sharpness : numpy.ndarray of float32, shape (K,), optional
    Sharpness of each corner vertex (default 10). Under ``"hoppe94"`` any positive value makes a corner.
cone_vertices : numpy.ndarray of int32, shape (Q,), optional
    Vertices tagged as cones (``"hoppe94"``; ignored under ``"opensubdiv"``, which has no cones).
crease_threshold : float, optional
    ``"hoppe94"``: an edge is a crease when its sharpness is positive and at least this (default 0).
boundary : {"edges", "edges-and-corners", "none"}, optional
    ``"edges-and-corners"`` makes boundary vertices with a single face corners, under either rule set
    (Blender's "Keep Corners"). Default ``"edges"``: boundary edges are creases. ``"none"``: the faces
    around a boundary vertex whose boundary edges are not all tagged infinitely sharp become holes
    (OpenSubdiv's VTX_BOUNDARY_NONE).
crease_method : {"uniform", "chaikin"}, optional
    ``"opensubdiv"``: how semi-sharp sharpness decays from level to level.
threads : int, optional
    Threads used by evaluation (1 or 2 on the target machines).
scalar : bool, optional
    Force the scalar reference kernel instead of the widest SIMD one the CPU runs.
memory_limit_bytes : int, optional
    Refuse (``MemoryError``) a refinement that would need more than this (default 4 GiB).
limit_surface : bool, optional
    Put the last level on the limit surface (Blender's "Use Limit Surface"); ``evaluate_with_normals``
    then also gives the limit normals. Default False.
uv_interpolation : {"none", "corners", "corners-plus1", "corners-plus2", "boundaries", "all"}, optional
    Where face-varying layers stay linear (OpenSubdiv's FVarLinearInterpolation 0..5): nowhere, at the
    corners of UV islands (the default, OpenSubdiv's), also at junctions, also at concave corners, along
    seams and boundaries, everywhere.
face_varying_indices : list of numpy.ndarray of int32, shape (M, 3), optional
    One face-varying layer per array: the value index at each corner (a UV map's ``vt`` indices). Corners
    of a vertex with the same index share a value; different indices make a seam there. Layer ``k`` has
    ``max(indices) + 1`` values; refine them with ``evaluate_face_varying(values, layer=k)``.
hole_triangles : numpy.ndarray of int32, shape (H,), optional
    Triangles that are holes: refined (the surface around them is unchanged) but left out of the output.
level_tables : {"auto", "stored", "derived"}, optional
    The refined levels' stencil tables: stored (fastest to evaluate again and again), or derived from the
    levels' connectivity as each evaluation runs (a plan about twice as quick to build and about 45 % smaller
    besides its output; each evaluation about 2.5x as long: for a plan evaluated once). Derived applies
    only to plans without ``limit_surface`` and face-varying layers, over two levels or more. "auto" (the
    default) derives them for results of about 20 million triangles and up.

Raises
------
TypeError
    An array argument is not a numpy array of the required dtype.
ValueError
    Wrong shape or layout, invalid option, invalid mesh or tags, negative levels.
MemoryError
    The refinement would need more than ``memory_limit_bytes`` (see ``required_bytes``).

Notes
-----
Output vertices are ordered as in the seed: at each level the old vertices keep their indices, then one new
vertex per edge of that level (``level_edges``). Child triangle ``4*f + k`` of a level has parent ``f``.
Array properties are read-only views of the plan's memory (no copy); they keep the plan alive.
)doc";

constexpr const char* kEvaluateDoc = R"doc(evaluate(values, out=None)

Refine per-vertex data (positions, weights, colours) on the plan's topology.

Parameters
----------
values : numpy.ndarray of float32, shape (N, C) or (N,)
    One row per input vertex, C-contiguous. Must be finite.
out : numpy.ndarray of float32, shape (N_out, C) or (N_out,), optional
    Where to write the result (C-contiguous, writeable, not overlapping ``values``). Default: a new array.

Returns
-------
numpy.ndarray of float32, shape (N_out, C) or (N_out,)
    ``out`` itself when given. Every channel is refined with the same weights.

Raises
------
ValueError
    Wrong shape or layout, or a non-finite value (``out`` may then be partly written).
)doc";

constexpr const char* kNormalsDoc = R"doc(evaluate_with_normals(positions, out=None, normals=None)

Refine positions to the limit surface and give its normals (the Plan needs ``limit_surface=True``).

Parameters
----------
positions : numpy.ndarray of float32, shape (N, C), C >= 3
    x, y, z first; any further channels are refined alike.
out : numpy.ndarray of float32, shape (N_out, C), optional
normals : numpy.ndarray of float32, shape (T_out, 3, 3), optional
    Where to write the results. Default: new arrays.

Returns
-------
tuple of numpy.ndarray
    ``(positions, normals)``: limit positions (N_out, C) and the unit normal at each corner of each output
    triangle (T_out, 3, 3). Across a crease or a boundary each side has its own normal (the normal of the
    surface on that side); elsewhere the corners of a vertex share one. Zero where the surface has no
    tangent plane (a degenerate neighbourhood).
)doc";

constexpr const char* kLimitNormalsDoc = R"doc(evaluate_with_limit_normals(positions, out=None, normals=None)

Refine positions to the limit surface and give its normals in compact form (the Plan needs ``limit_surface=True``):
each normal once, not once per corner.

Parameters
----------
positions : numpy.ndarray of float32, shape (N, C), C >= 3
    x, y, z first; any further channels are refined alike.
out : numpy.ndarray of float32, shape (N_out, C), optional
normals : numpy.ndarray of float32, shape (num_limit_normals, 3), optional
    Where to write the results. Default: new arrays.

Returns
-------
tuple of numpy.ndarray
    ``(positions, normals)``: limit positions (N_out, C) and the limit normals (num_limit_normals, 3): row v is
    vertex v's normal, rows from N_out on the normals of the sides of vertices whose fan infinitely sharp edges
    split into two sides or more (a vertex of one side, an open fan as at a boundary, has that side's normal as
    its own). ``normals[corner_normal_indices]`` is ``evaluate_with_normals``' per-corner array, bit for bit. A
    vertex of a split fan has a zero row of its own.
)doc";

constexpr const char* kFaceVaryingDoc = R"doc(evaluate_face_varying(values, out=None, *, layer=None)

Refine face-varying data (UVs).

Parameters
----------
values : numpy.ndarray of float32
    With ``layer=k``: shape (V, C) or (V,), one row per value of layer ``k`` (V = its largest index + 1),
    refined by the Plan's ``uv_interpolation`` (to the limit with ``limit_surface``); the result has one row
    per output value, placed on the output corners by ``face_varying_indices(k)``.
    Without a layer: shape (T, 3, C) or (T, 3), C values per corner of each input triangle, refined linearly
    within each face (``uv_interpolation="all"``), whatever the Plan's setting; the result has the shape
    (T_out, 3, C) or (T_out, 3), in the corner order of ``Plan.triangles``.
    Must be finite.
out : numpy.ndarray of float32, optional
    Where to write the result. Default: a new array.
layer : int, optional
    The face-varying layer (index into the Plan's ``face_varying_indices``).
)doc";

// The Plan docstring spells out the default memory limit.
static_assert(loopsub::Options{}.memory_limit_bytes == 4294967296u, "update kPlanDoc's memory_limit_bytes default");

}  // namespace

std::unique_ptr<PyPlan> build_plan(py::handle triangles, long long num_vertices, int levels, const OptionArgs& args,
                                   const std::vector<py::array>& welded_layers) {
    PlanInput in;
    read_input(in, triangles, num_vertices, levels, args, welded_layers);
    // All Python objects are read: the topology work runs without the GIL. `in` keeps the buffers alive.
    std::vector<int> layer_values;
    for (const loopsub::FaceVaryingLayer& layer : in.layers) layer_values.push_back(layer.num_values);
    py::gil_scoped_release nogil;
    return std::make_unique<PyPlan>(loopsub::Plan(in.mesh, in.options), in.mesh.num_triangles, std::move(layer_values));
}

py::array evaluate(py::object self, py::handle values, py::handle out) {
    PyPlan& p = self.cast<PyPlan&>();
    auto [in, channels] = read_vertex_values(values, "values", p.plan.num_input_vertices());
    std::vector<Dim> dims{{p.plan.num_output_vertices(), "N_out"}};
    if (in.ndim() == 2) dims.push_back({channels, "C"});
    py::array result = output_array(out, dims, in);
    if (channels == 0) return result;  // nothing to compute, and no data pointer worth handing to the core

    const float* src = data_of<float>(in);
    float* dst = static_cast<float*>(result.mutable_data());
    {
        // The arrays are held by `in` and `result` (destroyed after the GIL is back); the core touches no Python.
        py::gil_scoped_release nogil;
        std::lock_guard<std::mutex> lock(p.evaluate_mutex);
        p.plan.evaluate(loopsub::interleaved(src, channels), loopsub::interleaved(dst, channels));
    }
    return result;
}

// The plan's limit tables, or ValueError for a plan without the limit surface.
void require_limit(const PyPlan& p, const char* what) {
    if (!p.plan.options().limit_surface)
        throw py::value_error(std::string(what) +
                              ": the limit normals are the limit surface's; build the Plan with limit_surface=True");
}

// Positions in, refined positions and the limit normals out, in the shape normals_dims() gives (per corner, or
// compact; asked once the plan is known to have the limit surface): the checks both forms share, then
// `evaluate(positions in, positions out, normals)` without the GIL.
template <typename Dims, typename Evaluate>
py::tuple evaluate_positions_and_normals(PyPlan& p, const char* name, py::handle positions, py::handle out,
                                         py::handle normals_out, Dims normals_dims, Evaluate evaluate) {
    require_limit(p, name);
    py::array in = require_array<float>(positions, "positions", {{p.plan.num_input_vertices(), "N"}, {-1, "C"}});
    const int channels = checked_count(in.shape(1), "number of channels");
    if (channels < 3)
        throw py::value_error("positions must have at least 3 channels (x, y, z first), got " +
                              std::to_string(channels));
    py::array result = output_array(out, {{p.plan.num_output_vertices(), "N_out"}, {channels, "C"}}, in);
    py::array normals = output_array(normals_out, normals_dims(), in);
    if (overlaps(normals, result)) throw py::value_error("normals must not share memory with out");
    const float* src = data_of<float>(in);
    float* dst = static_cast<float*>(result.mutable_data());
    float* n = static_cast<float*>(normals.mutable_data());
    {
        py::gil_scoped_release nogil;
        std::lock_guard<std::mutex> lock(p.evaluate_mutex);
        evaluate(loopsub::interleaved(src, channels), loopsub::interleaved(dst, channels), n);
    }
    return py::make_tuple(result, normals);
}

py::tuple evaluate_with_normals(py::object self, py::handle positions, py::handle out, py::handle normals_out) {
    PyPlan& p = self.cast<PyPlan&>();
    return evaluate_positions_and_normals(
        p, "evaluate_with_normals", positions, out, normals_out,
        [&p] {
            return std::vector<Dim>{{p.plan.num_output_triangles(), "T_out"}, {3, "3"}, {3, "3"}};
        },
        [&p](auto in, auto result, float* normals) { p.plan.evaluate(in, result, normals); });
}

py::tuple evaluate_with_limit_normals(py::object self, py::handle positions, py::handle out, py::handle normals_out) {
    PyPlan& p = self.cast<PyPlan&>();
    return evaluate_positions_and_normals(
        p, "evaluate_with_limit_normals", positions, out, normals_out,
        [&p] {
            return std::vector<Dim>{{p.plan.num_limit_normals(), "num_limit_normals"}, {3, "3"}};
        },
        [&p](auto in, auto result, float* normals) {
            p.plan.evaluate(in, result, loopsub::Plan::LimitNormals{normals});
        });
}

// The output's edges' count, or ValueError for a plan that has none of its own (no levels, or holes).
int num_output_edges(const PyPlan& p) {
    try {
        return p.plan.num_output_edges();
    } catch (const std::logic_error& error) { throw py::value_error(error.what()); }
}

py::array evaluate_layer(PyPlan& p, int layer, py::handle values, py::handle out) {
    auto [in, channels] = read_vertex_values(values, "values", p.layer_values[layer]);
    std::vector<Dim> dims{{p.plan.num_output_face_varying_values(layer), "V_out"}};
    if (in.ndim() == 2) dims.push_back({channels, "C"});
    py::array result = output_array(out, dims, in);
    if (channels == 0) return result;
    const float* src = data_of<float>(in);
    float* dst = static_cast<float*>(result.mutable_data());
    {
        py::gil_scoped_release nogil;
        std::lock_guard<std::mutex> lock(p.evaluate_mutex);
        p.plan.evaluate_face_varying(layer, loopsub::interleaved(src, channels), loopsub::interleaved(dst, channels));
    }
    return result;
}

namespace {

py::tuple output_edges(PyPlan& p, py::handle edge_vertices_out, py::handle triangle_edges_out,
                       py::handle triangles_out) {
    const std::vector<Dim> edge_dims{{num_output_edges(p), "E_out"}, {2, "2"}};
    const std::vector<Dim> triangle_dims{{p.plan.num_output_triangles(), "M_out"}, {3, "3"}};
    auto array = [](py::handle out, const char* name, const std::vector<Dim>& dims) {
        if (out.is_none()) return new_array<std::int32_t>({dims[0].size, dims[1].size});
        return require_array<std::int32_t>(out, name, dims, /*writeable=*/true);
    };
    py::array edge_vertices = array(edge_vertices_out, "edge_vertices", edge_dims);
    py::array triangle_edges = array(triangle_edges_out, "triangle_edges", triangle_dims);
    const bool copy_triangles = !triangles_out.is_none();
    py::array triangles = copy_triangles ? array(triangles_out, "triangles", triangle_dims) : py::array();
    if (overlaps(edge_vertices, triangle_edges) ||
        (copy_triangles && (overlaps(triangles, edge_vertices) || overlaps(triangles, triangle_edges))))
        throw py::value_error("edge_vertices, triangle_edges and triangles must not share memory");
    auto* ends = static_cast<std::int32_t*>(edge_vertices.mutable_data());
    auto* sides = static_cast<std::int32_t*>(triangle_edges.mutable_data());
    auto* corners = copy_triangles ? static_cast<std::int32_t*>(triangles.mutable_data()) : nullptr;
    {
        py::gil_scoped_release nogil;
        p.plan.output_edges(ends, sides, corners);
    }
    return py::make_tuple(edge_vertices, triangle_edges);
}

py::array output_edge_parents(PyPlan& p, py::handle side_edges_in, py::handle parents_out) {
    const std::vector<Dim> side_dims{{p.num_input_triangles, "M"}, {3, "3"}};
    const py::array side_edges = require_array<std::int32_t>(side_edges_in, "side_edges", side_dims);
    const std::vector<Dim> parent_dims{{num_output_edges(p), "E_out"}};
    py::array parents = parents_out.is_none() ? new_array<std::int32_t>({parent_dims[0].size})
                                              : require_array<std::int32_t>(parents_out, "parents", parent_dims, true);
    if (overlaps(parents, side_edges)) throw py::value_error("side_edges and parents must not share memory");
    const auto* sides = static_cast<const std::int32_t*>(side_edges.data());
    auto* out = static_cast<std::int32_t*>(parents.mutable_data());
    {
        py::gil_scoped_release nogil;
        p.plan.output_edge_parents(sides, out);
    }
    return parents;
}

using PlanClass = py::class_<PyPlan>;

// Construction from the mesh and options, and the evaluations: vertex values, positions with their normals (per corner
// or compact), face-varying layers.
void bind_evaluation(PlanClass& plan) {
    plan.def(py::init([](py::handle triangles, long long num_vertices,
                         int levels LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_PARAMETER)) {
                 return build_plan(triangles, num_vertices, levels,
                                   OptionArgs{LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_VALUE)});
             }),
             py::arg("triangles"), py::arg("num_vertices"), py::arg("levels") = 1,
             py::kw_only() LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_ARG))
        .def("evaluate", &evaluate, kEvaluateDoc, py::arg("values"), py::arg("out") = py::none())
        .def("evaluate_with_normals", &evaluate_with_normals, kNormalsDoc, py::arg("positions"),
             py::arg("out") = py::none(), py::arg("normals") = py::none())
        .def("evaluate_with_limit_normals", &evaluate_with_limit_normals, kLimitNormalsDoc, py::arg("positions"),
             py::arg("out") = py::none(), py::arg("normals") = py::none())
        .def_property_readonly(
            "num_limit_normals",
            [](PyPlan& p) {
                require_limit(p, "num_limit_normals");
                return p.plan.num_limit_normals();
            },
            "Number of limit normals in compact form (evaluate_with_limit_normals): one per output vertex, then one "
            "per "
            "side of each vertex whose fan infinitely sharp edges split. ValueError without limit_surface.")
        .def_property_readonly(
            "corner_normal_indices",
            [](py::object self) {
                auto& p = self.cast<PyPlan&>();
                require_limit(p, "corner_normal_indices");
                return plan_view(p.plan.corner_normal_indices(), {p.plan.num_output_triangles(), 3}, self);
            },
            "(M_out, 3) int32, read-only view: at each corner of each output triangle, the row of its normal in "
            "evaluate_with_limit_normals' normals (v: vertex v's own; N_out + s: side s of a split fan). The same for "
            "every "
            "evaluation. ValueError without limit_surface.")
        .def("evaluate_face_varying", &evaluate_face_varying, kFaceVaryingDoc, py::arg("values"),
             py::arg("out") = py::none(), py::kw_only(), py::arg("layer") = py::none())
        .def(
            "face_varying_indices",
            [](py::object self, py::handle layer_arg) {
                PyPlan& p = self.cast<PyPlan&>();
                const int layer = layer_index(p, layer_arg);
                return plan_view(p.plan.output_face_varying_indices(layer), {p.plan.num_output_triangles(), 3}, self);
            },
            py::arg("layer"),
            "face_varying_indices(layer)\n\nint32 array (T_out, 3), read-only: the value index (into "
            "evaluate_face_varying(values, layer=layer)'s result) at each corner of each output triangle.")
        .def_property_readonly(
            "num_face_varying_layers", [](PyPlan& p) { return int(p.layer_values.size()); },
            "Number of face-varying layers (face_varying_indices given to the Plan).");
}

// What the plan was built with and its counts, its timings, its notes and its repr.
void bind_properties(PlanClass& plan) {
    plan.def_property_readonly(
            "limit_surface", [](PyPlan& p) { return p.plan.options().limit_surface; },
            "Whether the last level is put on the limit surface.")
        .def_property_readonly(
            "uv_interpolation", [](PyPlan& p) { return loopsub::option_name(p.plan.options().face_varying); },
            "How face-varying layers are interpolated (see the Plan's uv_interpolation).")
        .def_property_readonly(
            "level_tables", [](PyPlan& p) { return loopsub::option_name(p.plan.options().level_tables); },
            "The level_tables option the Plan was built with ('auto', 'stored' or 'derived').")
        .def_property_readonly(
            "levels", [](PyPlan& p) { return p.plan.levels(); }, "Levels of subdivision.")
        .def_property_readonly(
            "rules", [](PyPlan& p) { return loopsub::option_name(p.plan.options().rules); },
            "The rule set: 'hoppe94' or 'opensubdiv'.")
        .def_property_readonly(
            "notes", [](PyPlan& p) { return notes_of(p.plan.notes()); },
            "list: what the core's checks found to tell of the input that is no error, as diagnose() lists its notes: "
            "each edge two triangles run along the same way (kind 'runs_the_same_way': triangle index, its side "
            "corner, the other triangle other).")
        .def_property_readonly("num_input_vertices", [](PyPlan& p) { return p.plan.num_input_vertices(); })
        .def_property_readonly("num_input_triangles", [](PyPlan& p) { return p.num_input_triangles; })
        .def_property_readonly("num_output_vertices", [](PyPlan& p) { return p.plan.num_output_vertices(); })
        .def_property_readonly("num_output_triangles", [](PyPlan& p) { return p.plan.num_output_triangles(); })
        .def_property_readonly(
            "kernel", [](PyPlan& p) { return loopsub::kernel_name(p.plan.kernel()); },
            "Name of the evaluation kernel in use: 'scalar', 'sse4.1' or 'avx2'.")
        .def_property_readonly(
            "topology_ms", [](PyPlan& p) { return p.plan.topology_ms(); },
            "Milliseconds the constructor spent on the topology work.")
        .def_property_readonly(
            "last_evaluate_ms",
            [](PyPlan& p) {
                // Written by evaluate() without the GIL: read it under the same lock (and let others run meanwhile).
                py::gil_scoped_release nogil;
                std::lock_guard<std::mutex> lock(p.evaluate_mutex);
                return p.plan.last_evaluate_ms();
            },
            "Milliseconds the last evaluate() spent in the core.")
        .def("__repr__", [](PyPlan& p) {
            return "<_loopsub.Plan rules=" + std::string(loopsub::option_name(p.plan.options().rules)) +
                   " levels=" + std::to_string(p.plan.levels()) +
                   " vertices=" + std::to_string(p.plan.num_input_vertices()) + "->" +
                   std::to_string(p.plan.num_output_vertices()) +
                   " triangles=" + std::to_string(p.num_input_triangles) + "->" +
                   std::to_string(p.plan.num_output_triangles()) + ">";
        });
}

// The output mesh: its triangles, their parents and the output's tags (read-only views of the plan's memory).
void bind_output_mesh(PlanClass& plan) {
    plan.def_property_readonly(
            "triangles",
            [](py::object self) {
                auto& p = self.cast<PyPlan&>();
                return plan_view(p.plan.output_triangles(), {p.plan.num_output_triangles(), 3}, self);
            },
            "(M_out, 3) int32: the output triangles, winding kept (read-only view).")
        .def_property_readonly(
            "parent_triangles",
            [](py::object self) {
                auto& p = self.cast<PyPlan&>();
                return plan_view(p.plan.output_parent_triangles(), {p.plan.num_output_triangles()}, self);
            },
            "(M_out,) int32: for each output triangle, the input triangle it comes from (read-only view).")
        .def_property_readonly(
            "crease_edges", [](py::object self) { return tag_view(self, &loopsub::Plan::output_crease_edges, true); },
            "(K, 2) int32: the output's crease edges (read-only view).")
        .def_property_readonly(
            "crease_sharpness", [](py::object self) { return tag_view(self, &loopsub::Plan::output_crease_sharpness); },
            "(K,) float32: sharpness of the output's crease edges (read-only view).")
        .def_property_readonly(
            "corner_vertices", [](py::object self) { return tag_view(self, &loopsub::Plan::output_corner_vertices); },
            "(K,) int32: the output's corner vertices (read-only view).")
        .def_property_readonly(
            "corner_sharpness", [](py::object self) { return tag_view(self, &loopsub::Plan::output_corner_sharpness); },
            "(K,) float32: sharpness of the output's corner vertices (read-only view).")
        .def_property_readonly(
            "sharp_edges", [](py::object self) { return tag_view(self, &loopsub::Plan::output_sharp_edges, true); },
            "(S, 2) int32: every output edge the rules treat as sharp: creases that pass the rules, boundary and "
            "non-manifold edges (read-only view). With level_vertex_types(levels), what to tag the output with.")
        .def_property_readonly(
            "sharp_edge_sharpness",
            [](py::object self) { return tag_view(self, &loopsub::Plan::output_sharp_edge_sharpness); },
            "(S,) float32: sharpness of each of sharp_edges (10: infinitely sharp) (read-only view).")
        .def_property_readonly(
            "crease_edge_indices",
            [](py::object self) { return tag_view(self, &loopsub::Plan::output_crease_edge_indices); },
            "(K,) int32: crease_edges as numbers of output_edges()'s edges, for plans of at least one level "
            "(read-only view).")
        .def_property_readonly(
            "sharp_edge_indices",
            [](py::object self) { return tag_view(self, &loopsub::Plan::output_sharp_edge_indices); },
            "(S,) int32: sharp_edges as numbers of output_edges()'s edges, for plans of at least one level "
            "(read-only view).");
}

// The output's edges as the last split numbers them, and the input edges they lie on.
void bind_output_edges(PlanClass& plan) {
    plan.def_property_readonly(
            "num_output_edges", [](PyPlan& p) { return num_output_edges(p); },
            "int: the output's edges, as output_edges() gives them. ValueError for a plan of no levels or with "
            "holes.")
        .def(
            "output_edges", &output_edges, py::arg("edge_vertices") = py::none(),
            py::arg("triangle_edges") = py::none(), py::arg("triangles") = py::none(),
            "output_edges(edge_vertices=None, triangle_edges=None, triangles=None)\n\n(edge_vertices (E_out, 2) "
            "int32, triangle_edges (M_out, 3) int32): the output's edges as the last split numbers them (the halves of "
            "edge e of level levels - 1 are 2e and 2e + 1, the edges inside its face f are 2E + 3f + k), and each "
            "output triangle's edges (edge k joins corners k and k + 1): a mesh without an edge search. Written into "
            "the arrays given (C-contiguous, writeable int32 of those shapes, apart in memory: a mesh's own arrays, "
            "say), else into new ones. Given triangles ((M_out, 3) int32, the same rules), the output triangles are "
            "copied there in the same pass (a mesh's corner vertices). ValueError for a plan of no levels or with "
            "holes.")
        .def(
            "output_edge_parents", &output_edge_parents, py::arg("side_edges"), py::arg("parents") = py::none(),
            "output_edge_parents(side_edges, parents=None)\n\n(E_out,) int32: for each output edge (output_edges()' "
            "order), the number of the input edge it lies on, -1 inside an input triangle. side_edges (M, 3) int32: "
            "per input triangle, the caller's number of its edge k (from corner k to k + 1), -1 for none (a diagonal "
            "the caller's triangulation added); an edge given several numbers takes the greatest. Written into parents "
            "when given (C-contiguous, writeable). ValueError for a plan of no levels or with holes.");
}

// The levels: each one's edges, vertex count and vertex classes.
void bind_levels(PlanClass& plan) {
    plan.def(
            "level_edges",
            [](py::object self, int level) {
                auto& p = self.cast<PyPlan&>();
                if (level < 0 || level >= p.plan.levels())
                    throw py::index_error("level must be in [0, " + std::to_string(p.plan.levels()) + "), got " +
                                          std::to_string(level));
                const auto& v = p.plan.level_edges(level);
                return plan_view(v.data(), {py::ssize_t(v.size() / 2), 2}, self);
            },
            py::arg("level"),
            "level_edges(level)\n\n(E, 2) int32: the edges of level L; edge k becomes vertex level_num_vertices(L) + k "
            "of level L+1.")
        .def(
            "level_num_vertices",
            [](PyPlan& p, int level) {
                if (level < 0 || level > p.plan.levels())
                    throw py::index_error("level must be in [0, " + std::to_string(p.plan.levels()) + "], got " +
                                          std::to_string(level));
                return p.plan.level_num_vertices(level);
            },
            py::arg("level"), "level_num_vertices(level)\n\nNumber of vertices of level L (0 <= L <= levels).")
        .def(
            "level_vertex_types",
            [](py::object self, int level) {
                auto& p = self.cast<PyPlan&>();
                if (level < 0 || level > p.plan.levels() || (p.plan.levels() == 0 && !p.plan.options().limit_surface))
                    throw py::index_error("level must be in [0, " + std::to_string(p.plan.levels()) + "], got " +
                                          std::to_string(level) +
                                          (p.plan.levels() == 0 ? " (a plan of no levels has no classes)" : ""));
                const auto& v = p.plan.level_vertex_types(level);
                static_assert(sizeof(loopsub::VertexType) == 1, "VertexType is viewed as uint8");
                return plan_view(reinterpret_cast<const std::uint8_t*>(v.data()), {py::ssize_t(v.size())}, self);
            },
            py::arg("level"),
            "level_vertex_types(level)\n\n(N_L,) uint8: the class of each vertex of level L (0 <= L <= levels) as used "
            "to "
            "reposition it; for L = levels, the output's classes (as a deeper plan or the limit uses them: what to tag "
            "the result with). Names in VERTEX_TYPES (read-only view).");
}

void bind_option_names(py::module_& m) {
    m.def(
        "option_names",
        [] {
            py::dict names;
            auto add = [&](const char* keyword, loopsub::OptionNames table) {
                py::tuple values(table.count);
                for (int i = 0; i < table.count; ++i) values[std::size_t(i)] = py::str(table.names[i]);
                names[keyword] = values;
            };
            add("rules", loopsub::option_names<loopsub::Rules>());
            add("boundary", loopsub::option_names<loopsub::Boundary>());
            add("crease_method", loopsub::option_names<loopsub::CreaseMethod>());
            add("uv_interpolation", loopsub::option_names<loopsub::FaceVaryingInterpolation>());
            add("level_tables", loopsub::option_names<loopsub::LevelTables>());
            return names;
        },
        "option_names()\n\nThe values each option of Plan() and subdivide() takes, by keyword: a new dict of tuples of "
        "names, e.g. {'rules': ('hoppe94', 'opensubdiv'), ...}.");
}

}  // namespace

void bind_plan(py::module_& m) {
    PlanClass plan(m, "Plan", kPlanDoc);
    bind_evaluation(plan);
    bind_properties(plan);
    bind_output_mesh(plan);
    bind_output_edges(plan);
    bind_levels(plan);
    bind_option_names(m);
}

}  // namespace loopsub::python
