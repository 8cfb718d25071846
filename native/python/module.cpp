// The Python module `_loopsub`: numpy in, numpy out, no copies, the GIL released while the core runs.
//
// Conventions, so that Blender (and anyone else) gets errors instead of silent conversions:
//   * every input array must already be a numpy array of exactly the right dtype (float32 / int32), C-contiguous,
//     aligned and of the right shape; it is then read in place. A wrong dtype raises TypeError, a wrong shape or
//     layout ValueError, each naming the argument, what was expected and what was given;
//   * loopsub::InputError becomes ValueError, loopsub::MemoryLimitError becomes MemoryError (with the size);
//   * arrays handed out by a Plan are read-only views of the plan's own memory whose base is the Plan object, so
//     the plan lives as long as any of them does.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "loopsub/loopsub.h"

namespace py = pybind11;

namespace {

// ---------------------------------------------------------------------------------------------------------------
// Input checking

template <typename T>
const char* dtype_name();
template <>
const char* dtype_name<float>() { return "float32"; }
template <>
const char* dtype_name<std::int32_t>() { return "int32"; }

// One expected dimension: a fixed size, or any size (size < 0) shown by its symbol.
struct Dim {
    py::ssize_t size;
    const char* symbol;
};

std::string describe_shape(const std::vector<Dim>& dims) {
    std::ostringstream s;
    s << '(';
    for (std::size_t i = 0; i < dims.size(); ++i) {
        if (i) s << ", ";
        if (dims[i].size < 0)
            s << dims[i].symbol;
        else if (dims[i].symbol[0] >= '0' && dims[i].symbol[0] <= '9')
            s << dims[i].size;  // a literal such as the 3 of (M, 3)
        else
            s << dims[i].symbol << '=' << dims[i].size;
    }
    s << (dims.size() == 1 ? ",)" : ")");
    return s.str();
}

std::string actual_shape(const py::array& a) {
    std::ostringstream s;
    s << '(';
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
    s << (a.ndim() == 1 ? ",)" : ")");
    return s.str();
}

bool shape_matches(const py::array& a, const std::vector<Dim>& dims) {
    if (a.ndim() != py::ssize_t(dims.size())) return false;
    for (std::size_t i = 0; i < dims.size(); ++i)
        if (dims[i].size >= 0 && a.shape(py::ssize_t(i)) != dims[i].size) return false;
    return true;
}

// The array `obj` is, if it is a numpy array of dtype T (TypeError otherwise). Shape and layout are checked apart,
// so that an argument that may take one of two shapes gets one message listing both.
template <typename T>
py::array require_dtype(py::handle obj, const char* name) {
    if (!py::isinstance<py::array>(obj))
        throw py::type_error(std::string(name) + " must be a numpy.ndarray of dtype " + dtype_name<T>() + ", got " +
                             std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
    auto a = py::reinterpret_borrow<py::array>(obj);
    // EquivTypes, not identity: np.intc and np.int32 are the same type here, a byte-swapped float32 is not.
    if (!py::array_t<T>::check_(a))
        throw py::type_error(std::string(name) + " must have dtype " + dtype_name<T>() + ", got " +
                             std::string(py::str(a.dtype())) + " (this module never converts: use " + name +
                             ".astype(numpy." + dtype_name<T>() + "))");
    return a;
}

// The core reads the data as a flat T array: it must be C-contiguous and aligned (and writeable for outputs).
void require_layout(const py::array& a, const char* name, bool writeable) {
    if (!(a.flags() & py::array::c_style))
        throw py::value_error(std::string(name) + " must be C-contiguous, got a strided array of shape " +
                              actual_shape(a) + " (use numpy.ascontiguousarray(" + name + "))");
    if (!(a.flags() & py::detail::npy_api::NPY_ARRAY_ALIGNED_))
        throw py::value_error(std::string(name) + " must be aligned to its dtype, got an unaligned buffer");
    if (writeable && !a.writeable()) throw py::value_error(std::string(name) + " must be writeable, got a read-only array");
}

template <typename T>
py::array require_array(py::handle obj, const char* name, const std::vector<Dim>& dims, bool writeable = false) {
    py::array a = require_dtype<T>(obj, name);
    if (!shape_matches(a, dims))
        throw py::value_error(std::string(name) + " must have shape " + describe_shape(dims) + ", got " + actual_shape(a));
    require_layout(a, name, writeable);
    return a;
}

// The core counts in int: larger inputs are refused rather than truncated.
int checked_count(long long n, const char* what) {
    if (n > std::numeric_limits<int>::max())
        throw py::value_error(std::string(what) + " " + std::to_string(n) + " exceeds the supported maximum " +
                              std::to_string(std::numeric_limits<int>::max()));
    return int(n);
}

template <typename T>
const T* data_of(const py::array& a) {
    return static_cast<const T*>(a.data());
}

// Writing the output over the input would read already-overwritten values mid-evaluation.
bool overlaps(const py::array& a, const py::array& b) {
    auto lo_a = reinterpret_cast<std::uintptr_t>(a.data()), lo_b = reinterpret_cast<std::uintptr_t>(b.data());
    auto hi_a = lo_a + std::uintptr_t(a.nbytes()), hi_b = lo_b + std::uintptr_t(b.nbytes());
    return a.nbytes() > 0 && b.nbytes() > 0 && lo_a < hi_b && lo_b < hi_a;
}

// ---------------------------------------------------------------------------------------------------------------
// Options

loopsub::Rules parse_rules(const std::string& s) {
    if (s == "hoppe94") return loopsub::Rules::Hoppe94;
    if (s == "opensubdiv") return loopsub::Rules::OpenSubdiv;
    throw py::value_error("rules must be 'hoppe94' or 'opensubdiv', got '" + s + "'");
}

loopsub::Boundary parse_boundary(const std::string& s) {
    if (s == "edges") return loopsub::Boundary::EdgesOnly;
    if (s == "edges-and-corners") return loopsub::Boundary::EdgesAndCorners;
    if (s == "none") return loopsub::Boundary::None;
    throw py::value_error("boundary must be 'edges', 'edges-and-corners' or 'none', got '" + s + "'");
}

// The position of `s` among an enum's names (listed in its order), or -1.
template <std::size_t N>
int name_index(const char* const (&names)[N], const std::string& s) {
    for (std::size_t m = 0; m < N; ++m)
        if (s == names[m]) return int(m);
    return -1;
}

// The names of the CLI's --uv-interpolation, in OpenSubdiv's order (loopsub::FaceVaryingInterpolation).
const char* const kUvInterpolations[] = {"none", "corners", "corners-plus1", "corners-plus2", "boundaries", "all"};

loopsub::FaceVaryingInterpolation parse_uv_interpolation(const std::string& s) {
    const int m = name_index(kUvInterpolations, s);
    if (m < 0)
        throw py::value_error("uv_interpolation must be one of 'none', 'corners', 'corners-plus1', 'corners-plus2', "
                              "'boundaries', 'all', got '" + s + "'");
    return loopsub::FaceVaryingInterpolation(m);
}

// loopsub::LevelTables, in its order.
const char* const kLevelTables[] = {"auto", "stored", "derived"};

loopsub::LevelTables parse_level_tables(const std::string& s) {
    const int m = name_index(kLevelTables, s);
    if (m < 0) throw py::value_error("level_tables must be 'auto', 'stored' or 'derived', got '" + s + "'");
    return loopsub::LevelTables(m);
}

loopsub::CreaseMethod parse_crease_method(const std::string& s) {
    if (s == "uniform") return loopsub::CreaseMethod::Uniform;
    if (s == "chaikin") return loopsub::CreaseMethod::Chaikin;
    throw py::value_error("crease_method must be 'uniform' or 'chaikin', got '" + s + "'");
}

const char* rules_name(loopsub::Rules r) { return r == loopsub::Rules::Hoppe94 ? "hoppe94" : "opensubdiv"; }

// Everything a Plan is built from, read from Python while the GIL is held. The py::array members keep the
// caller's buffers alive (and referenced by `mesh`) while the core runs without the GIL.
struct PlanInput {
    py::array triangles, crease_edges, crease_sharpness, corner_vertices, corner_sharpness, cone_vertices, holes;
    std::vector<float> default_crease_sharpness, default_corner_sharpness;  // when only the tags are given
    std::vector<py::array> layer_arrays;                 // face_varying_indices, as given
    std::vector<std::vector<std::int32_t>> welded_layers;  // subdivide(): indices of per-corner values joined
    std::vector<loopsub::FaceVaryingLayer> layers;
    loopsub::MeshView mesh;
    loopsub::Options options;
};

struct OptionArgs {
    std::string rules, boundary, crease_method;
    py::object crease_edges, crease_sharpness, corner_vertices, corner_sharpness, cone_vertices;
    double crease_threshold;
    int threads;
    bool scalar;
    long long memory_limit_bytes;
    bool limit_surface;
    std::string uv_interpolation;
    py::object face_varying_indices, hole_triangles;
    std::string level_tables;
};

void read_input(PlanInput& in, py::handle triangles, long long num_vertices, int levels, const OptionArgs& o) {
    // levels and threads are checked by the core, before it starts a thread.
    if (num_vertices < 0) throw py::value_error("num_vertices must be >= 0, got " + std::to_string(num_vertices));
    if (o.memory_limit_bytes < 0)
        throw py::value_error("memory_limit_bytes must be >= 0, got " + std::to_string(o.memory_limit_bytes));
    if (!std::isfinite(o.crease_threshold))
        throw py::value_error("crease_threshold must be finite, got " + std::to_string(o.crease_threshold));

    loopsub::Options& opt = in.options;
    opt.rules = parse_rules(o.rules);
    opt.boundary = parse_boundary(o.boundary);
    opt.crease_method = parse_crease_method(o.crease_method);
    opt.levels = levels;
    opt.crease_threshold = float(o.crease_threshold);
    opt.threads = o.threads;
    opt.kernel = o.scalar ? loopsub::Kernel::Scalar : loopsub::Kernel::Auto;
    opt.memory_limit_bytes = std::uint64_t(o.memory_limit_bytes);
    opt.limit_surface = o.limit_surface;
    opt.face_varying = parse_uv_interpolation(o.uv_interpolation);
    opt.level_tables = parse_level_tables(o.level_tables);

    loopsub::MeshView& mesh = in.mesh;
    mesh.num_vertices = checked_count(num_vertices, "num_vertices");
    in.triangles = require_array<std::int32_t>(triangles, "triangles", {{-1, "M"}, {3, "3"}});
    mesh.triangles = data_of<std::int32_t>(in.triangles);
    mesh.num_triangles = checked_count(in.triangles.shape(0), "number of triangles");

    if (!o.crease_edges.is_none()) {
        in.crease_edges = require_array<std::int32_t>(o.crease_edges, "crease_edges", {{-1, "K"}, {2, "2"}});
        const py::ssize_t k = in.crease_edges.shape(0);
        mesh.num_crease_edges = checked_count(k, "number of crease edges");
        mesh.crease_edges = data_of<std::int32_t>(in.crease_edges);
        if (o.crease_sharpness.is_none()) {
            // Tags without sharpness are plain creases: infinitely sharp, as OpenSubdiv's SHARPNESS_INFINITE.
            in.default_crease_sharpness.assign(std::size_t(k), loopsub::kInfiniteSharpness);
            mesh.crease_sharpness = in.default_crease_sharpness.data();
        } else {
            in.crease_sharpness = require_array<float>(o.crease_sharpness, "crease_sharpness", {{k, "K"}});
            mesh.crease_sharpness = data_of<float>(in.crease_sharpness);
        }
    } else if (!o.crease_sharpness.is_none()) {
        throw py::value_error("crease_sharpness was given without crease_edges");
    }

    if (!o.corner_vertices.is_none()) {
        in.corner_vertices = require_array<std::int32_t>(o.corner_vertices, "corner_vertices", {{-1, "K"}});
        const py::ssize_t k = in.corner_vertices.shape(0);
        mesh.num_corners = checked_count(k, "number of corner vertices");
        mesh.corner_vertices = data_of<std::int32_t>(in.corner_vertices);
        if (o.corner_sharpness.is_none()) {
            in.default_corner_sharpness.assign(std::size_t(k), loopsub::kInfiniteSharpness);
            mesh.corner_sharpness = in.default_corner_sharpness.data();
        } else {
            in.corner_sharpness = require_array<float>(o.corner_sharpness, "corner_sharpness", {{k, "K"}});
            mesh.corner_sharpness = data_of<float>(in.corner_sharpness);
        }
    } else if (!o.corner_sharpness.is_none()) {
        throw py::value_error("corner_sharpness was given without corner_vertices");
    }

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
            in.layer_arrays.push_back(require_array<std::int32_t>(item, name.c_str(), {{mesh.num_triangles, "M"}, {3, "3"}}));
        }
    }
    for (const py::array& a : in.layer_arrays) {
        // A layer has as many values as its largest index says; evaluate_face_varying wants exactly that many.
        const std::int32_t* indices = data_of<std::int32_t>(a);
        const std::int32_t* largest = std::max_element(indices, indices + 3 * std::size_t(mesh.num_triangles));
        in.layers.push_back({indices, largest == indices + 3 * std::size_t(mesh.num_triangles) ? 0 : std::max(*largest + 1, 0)});
    }
    for (const std::vector<std::int32_t>& indices : in.welded_layers) {
        const auto largest = std::max_element(indices.begin(), indices.end());
        in.layers.push_back({indices.data(), largest == indices.end() ? 0 : *largest + 1});
    }
    mesh.face_varying = in.layers.data();
    mesh.num_face_varying = int(in.layers.size());
}

// ---------------------------------------------------------------------------------------------------------------
// The Plan object

struct PyPlan {
    PyPlan(loopsub::Plan&& p, int triangles, std::vector<int> values)
        : plan(std::move(p)), num_input_triangles(triangles), layer_values(std::move(values)) {}
    loopsub::Plan plan;
    int num_input_triangles;  // the core does not keep it; face-varying input is checked against it
    std::vector<int> layer_values;  // values of each face-varying layer
    // Plan::evaluate is not reentrant (it owns scratch buffers) and runs without the GIL, so two Python threads
    // evaluating one plan must take turns.
    std::mutex evaluate_mutex;
};

std::unique_ptr<PyPlan> build_plan(py::handle triangles, long long num_vertices, int levels, const OptionArgs& args,
                                   std::vector<std::vector<std::int32_t>> welded_layers = {}) {
    PlanInput in;
    in.welded_layers = std::move(welded_layers);
    read_input(in, triangles, num_vertices, levels, args);
    // All Python objects are read: the topology work runs without the GIL. `in` keeps the buffers alive.
    std::vector<int> layer_values;
    for (const loopsub::FaceVaryingLayer& layer : in.layers) layer_values.push_back(layer.num_values);
    py::gil_scoped_release nogil;
    return std::make_unique<PyPlan>(loopsub::Plan(in.mesh, in.options), in.mesh.num_triangles, std::move(layer_values));
}

// A read-only numpy view of memory owned by the plan; `base` (the Python Plan) stays alive as long as the view.
template <typename T>
py::array plan_view(const T* data, std::vector<py::ssize_t> shape, py::handle base) {
    py::array a(py::dtype::of<T>(), std::move(shape), data, base);
    a.attr("setflags")(py::arg("write") = false);
    return a;
}

// Values per vertex: (N, C), or (N,) for one channel. Returns the checked array and C.
std::pair<py::array, int> read_vertex_values(py::handle values, const char* name, int num_vertices) {
    py::array a = require_dtype<float>(values, name);
    const bool ok = (a.ndim() == 1 || a.ndim() == 2) && a.shape(0) == num_vertices;
    if (!ok)
        throw py::value_error(std::string(name) + " must have shape (N=" + std::to_string(num_vertices) +
                              ", C) or (N=" + std::to_string(num_vertices) + ",), got " + actual_shape(a));
    require_layout(a, name, false);
    return {a, a.ndim() == 2 ? checked_count(a.shape(1), "number of channels") : 1};
}

// Values per triangle corner: (T, 3, C), or (T, 3) for one channel.
std::pair<py::array, int> read_corner_values(py::handle values, const char* name, int num_triangles) {
    py::array a = require_dtype<float>(values, name);
    const bool ok = (a.ndim() == 2 || a.ndim() == 3) && a.shape(0) == num_triangles && a.shape(1) == 3;
    if (!ok)
        throw py::value_error(std::string(name) + " must have shape (T=" + std::to_string(num_triangles) +
                              ", 3, C) or (T=" + std::to_string(num_triangles) + ", 3), got " + actual_shape(a));
    require_layout(a, name, false);
    return {a, a.ndim() == 3 ? checked_count(a.shape(2), "number of channels") : 1};
}

// The output array: `out` checked against the expected shape, or a new uninitialised array of that shape.
py::array output_array(py::handle out, const std::vector<Dim>& dims, const py::array& input) {
    if (out.is_none()) {
        std::vector<py::ssize_t> shape;
        for (const Dim& d : dims) shape.push_back(d.size);
        return py::array(py::dtype::of<float>(), shape);
    }
    py::array a = require_array<float>(out, "out", dims, /*writeable=*/true);
    if (overlaps(a, input)) throw py::value_error("out must not share memory with the input values");
    return a;
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

py::tuple evaluate_with_normals(py::object self, py::handle positions, py::handle out, py::handle normals_out) {
    PyPlan& p = self.cast<PyPlan&>();
    if (!p.plan.options().limit_surface)
        throw py::value_error("evaluate_with_normals: the normals are the limit surface's; build the Plan with limit_surface=True");
    py::array in = require_array<float>(positions, "positions", {{p.plan.num_input_vertices(), "N"}, {-1, "C"}});
    const int channels = checked_count(in.shape(1), "number of channels");
    if (channels < 3) throw py::value_error("positions must have at least 3 channels (x, y, z first), got " + std::to_string(channels));
    py::array result = output_array(out, {{p.plan.num_output_vertices(), "N_out"}, {channels, "C"}}, in);
    py::array normals = output_array(normals_out, {{p.plan.num_output_triangles(), "T_out"}, {3, "3"}, {3, "3"}}, in);
    if (overlaps(normals, result)) throw py::value_error("normals must not share memory with out");
    const float* src = data_of<float>(in);
    float* dst = static_cast<float*>(result.mutable_data());
    float* n = static_cast<float*>(normals.mutable_data());
    {
        py::gil_scoped_release nogil;
        std::lock_guard<std::mutex> lock(p.evaluate_mutex);
        p.plan.evaluate(loopsub::interleaved(src, channels), loopsub::interleaved(dst, channels), n);
    }
    return py::make_tuple(result, normals);
}

// A face-varying layer's index as the caller gave it: any integer (numpy's too; a huge one is out of range, not a
// failed conversion), checked against the plan's layers.
int layer_index(const PyPlan& p, py::handle layer) {
    const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(layer.ptr()));
    if (!index) {
        PyErr_Clear();
        throw py::type_error("layer must be an integer, got " + std::string(py::str(py::type::handle_of(layer).attr("__name__"))));
    }
    int overflow = 0;
    const long long k = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
    if (overflow != 0 || k < 0 || k >= static_cast<long long>(p.layer_values.size()))
        throw py::value_error("layer " + std::string(py::str(index)) + " is not a face-varying layer of this Plan (it has " +
                              std::to_string(p.layer_values.size()) + ")");
    return int(k);
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
    const std::size_t n = std::size_t(p.num_input_triangles) * 3 * std::size_t(channels);
    std::size_t bad = n;
    {
        py::gil_scoped_release nogil;
        // Linear interpolation would spread a NaN or an infinity silently: refuse it, as evaluate() does.
        for (std::size_t i = 0; i < n; ++i)
            if (!std::isfinite(src[i])) {
                bad = i;
                break;
            }
        if (bad == n) p.plan.evaluate_face_varying(src, dst, channels);  // const: safe next to evaluate()
    }
    if (bad != n) {
        const std::size_t c = bad % std::size_t(channels), corner = bad / std::size_t(channels) % 3,
                          t = bad / std::size_t(channels) / 3;
        throw py::value_error("face-varying values must be finite: triangle " + std::to_string(t) + ", corner " +
                              std::to_string(corner) + ", channel " + std::to_string(c) + " is " +
                              std::to_string(src[bad]));
    }
    return result;
}

// ---------------------------------------------------------------------------------------------------------------
// subdivide(): the one-shot call

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

py::dict subdivide(py::handle positions, py::handle triangles, int levels, const OptionArgs& args, py::handle vertex_data,
                   py::handle face_varying) {
    py::array pos = require_array<float>(positions, "positions", {{-1, "N"}, {3, "3"}});
    // Every array is checked before the (possibly long) topology work, so a bad argument fails fast.
    py::array tris = require_array<std::int32_t>(triangles, "triangles", {{-1, "M"}, {3, "3"}});
    const int n = checked_count(pos.shape(0), "number of vertices");
    const int m = checked_count(tris.shape(0), "number of triangles");
    auto check_vertex = [&](py::handle a, const std::string& name) { read_vertex_values(a, name.c_str(), n); };
    auto check_corner = [&](py::handle a, const std::string& name) { read_corner_values(a, name.c_str(), m); };
    auto check_all = [](py::handle data, const char* name, auto check) {
        if (data.is_none()) return;
        if (py::isinstance<py::dict>(data)) {
            for (auto item : py::reinterpret_borrow<py::dict>(data))
                check(item.second, std::string(name) + "[" + std::string(py::repr(item.first)) + "]");
        } else {
            check(data, name);
        }
    };
    check_all(vertex_data, "vertex_data", check_vertex);
    check_all(face_varying, "face_varying", check_corner);

    // Per-corner face-varying arrays become layers: corners of a vertex with equal values (bit for bit) share a value.
    std::vector<py::array> corner_arrays;
    if (!face_varying.is_none()) {
        if (py::isinstance<py::dict>(face_varying)) {
            for (auto item : py::reinterpret_borrow<py::dict>(face_varying)) corner_arrays.push_back(py::reinterpret_borrow<py::array>(item.second));
        } else {
            corner_arrays.push_back(py::reinterpret_borrow<py::array>(face_varying));
        }
    }
    const std::int32_t* corner_vertices = data_of<std::int32_t>(tris);
    std::vector<std::vector<std::int32_t>> welded;
    std::vector<py::array> layer_values;
    for (const py::array& a : corner_arrays) {
        const std::size_t channels = a.ndim() == 3 ? std::size_t(a.shape(2)) : 1, corners = 3 * std::size_t(m);
        const float* v = data_of<float>(a);
        // Checked here, where the value's place is still its corner.
        for (std::size_t i = 0; i < corners * channels; ++i)
            if (!std::isfinite(v[i]))
                throw py::value_error("face-varying values must be finite: triangle " + std::to_string(i / channels / 3) +
                                      ", corner " + std::to_string(i / channels % 3) + ", channel " + std::to_string(i % channels) +
                                      " is " + std::to_string(v[i]));
        std::vector<std::int32_t> order(corners);
        std::iota(order.begin(), order.end(), 0);
        auto less = [&](std::int32_t x, std::int32_t y) {
            if (corner_vertices[x] != corner_vertices[y]) return corner_vertices[x] < corner_vertices[y];
            return std::memcmp(v + x * channels, v + y * channels, channels * sizeof(float)) < 0;
        };
        std::sort(order.begin(), order.end(), less);
        std::vector<std::int32_t>& indices = welded.emplace_back(corners);
        std::vector<std::int32_t> firsts;
        for (std::size_t i = 0; i < corners; ++i) {
            if (i == 0 || less(order[i - 1], order[i])) firsts.push_back(order[i]);
            indices[order[i]] = std::int32_t(firsts.size() - 1);
        }
        py::array_t<float> values({py::ssize_t(firsts.size()), py::ssize_t(channels)});
        for (std::size_t k = 0; k < firsts.size(); ++k)
            std::copy_n(v + firsts[k] * channels, channels, values.mutable_data() + k * channels);
        layer_values.push_back(a.ndim() == 3 ? py::array(values) : py::array(values.reshape({py::ssize_t(firsts.size())})));
    }
    const int first_welded = args.face_varying_indices.is_none() ? 0 : int(py::len(args.face_varying_indices));
    py::object plan = py::cast(build_plan(tris, n, levels, args, std::move(welded)));
    const py::handle none = py::none();
    auto eval_vertex = [&](py::handle a) { return evaluate(plan, a, none); };
    std::size_t next_layer = 0;
    auto eval_corner = [&](py::handle) {
        // Refined per value, then spread to the output's corners.
        PyPlan& q = plan.cast<PyPlan&>();
        const int layer = first_welded + int(next_layer);
        const py::array values = evaluate_layer(q, layer, layer_values[next_layer++], none);
        const std::size_t channels = values.ndim() == 2 ? std::size_t(values.shape(1)) : 1;
        const py::ssize_t t_out = q.plan.num_output_triangles();
        std::vector<py::ssize_t> shape{t_out, 3};
        if (values.ndim() == 2) shape.push_back(py::ssize_t(channels));
        py::array result(py::dtype::of<float>(), shape);
        const std::int32_t* indices = q.plan.output_face_varying_indices(layer);
        const float* src = data_of<float>(values);
        float* dst = static_cast<float*>(result.mutable_data());
        for (py::ssize_t c = 0; c < 3 * t_out; ++c) std::copy_n(src + std::size_t(indices[c]) * channels, channels, dst + c * channels);
        return result;
    };

    PyPlan& p = plan.cast<PyPlan&>();
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
    const auto& ce = p.plan.output_crease_edges();
    r["crease_edges"] = plan_view(ce.data(), {py::ssize_t(ce.size() / 2), 2}, plan);
    r["crease_sharpness"] = plan_view(p.plan.output_crease_sharpness().data(),
                                      {py::ssize_t(p.plan.output_crease_sharpness().size())}, plan);
    r["corner_vertices"] = plan_view(p.plan.output_corner_vertices().data(),
                                     {py::ssize_t(p.plan.output_corner_vertices().size())}, plan);
    r["corner_sharpness"] = plan_view(p.plan.output_corner_sharpness().data(),
                                      {py::ssize_t(p.plan.output_corner_sharpness().size())}, plan);
    r["vertex_data"] = map_data(vertex_data, eval_vertex);
    r["face_varying"] = map_data(face_varying, eval_corner);
    r["plan"] = plan;
    return r;
}

// ---------------------------------------------------------------------------------------------------------------
// Errors

std::string human_bytes(std::uint64_t bytes) {
    std::ostringstream s;
    s.precision(3);
    if (bytes >= (std::uint64_t(1) << 30))
        s << double(bytes) / double(std::uint64_t(1) << 30) << " GiB";
    else if (bytes >= (std::uint64_t(1) << 20))
        s << double(bytes) / double(std::uint64_t(1) << 20) << " MiB";
    else
        s << bytes << " bytes";
    return s.str();
}

void translate_exception(std::exception_ptr p) {
    try {
        if (p) std::rethrow_exception(p);
    } catch (const loopsub::MemoryLimitError& e) {
        // The message must say how much: the core's usually does; otherwise it is added. The exception also
        // carries the number as `required_bytes`, for callers that want to offer a lower level.
        std::string msg = e.what();
        if (msg.find(std::to_string(e.required_bytes)) == std::string::npos)
            msg += " (requires " + std::to_string(e.required_bytes) + " bytes = " + human_bytes(e.required_bytes) + ")";
        py::object exc = py::reinterpret_steal<py::object>(PyObject_CallFunction(PyExc_MemoryError, "s", msg.c_str()));
        if (!exc) return;  // PyObject_CallFunction set its own error
        exc.attr("required_bytes") = e.required_bytes;
        PyErr_SetObject(PyExc_MemoryError, exc.ptr());
    } catch (const loopsub::InputError& e) {
        PyErr_SetString(PyExc_ValueError, e.what());
    }
}

// ---------------------------------------------------------------------------------------------------------------
// Docstrings (numpydoc)

constexpr const char* kModuleDoc = R"doc(Loop subdivision of triangle meshes with creases.

Two rule sets: ``"hoppe94"`` (the GDC'99 seed's rules after Hoppe et al. 94: smooth, dart,
regular and irregular crease, corner and cone vertices) and ``"opensubdiv"`` (OpenSubdiv's Loop
scheme: semi-sharp creases, vertex sharpness, Chaikin creasing, both boundary modes).

Arrays are numpy arrays used in place, never converted: vertex data is ``float32``, indices are
``int32``, every array C-contiguous. A wrong dtype raises ``TypeError``; a wrong shape or layout,
invalid mesh or tag (index out of range, degenerate triangle, non-finite value, negative levels)
raises ``ValueError``; a refinement past ``memory_limit_bytes`` raises ``MemoryError`` whose
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

constexpr const char* kPlanDoc = R"doc(Plan(triangles, num_vertices, levels=1, *, rules="hoppe94", crease_edges=None, crease_sharpness=None, corner_vertices=None, corner_sharpness=None, cone_vertices=None, crease_threshold=0.0, boundary="edges", crease_method="uniform", threads=1, scalar=False, memory_limit_bytes=4294967296, limit_surface=False, uv_interpolation="corners", face_varying_indices=None, hole_triangles=None, level_tables="auto")

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

constexpr const char* kSubdivideDoc = R"doc(subdivide(positions, triangles, levels=1, *, <the options of Plan>, vertex_data=None, face_varying=None)

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
    (bit for bit) share one value, different values make a seam there.

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

// The Plan docstring spells out the default memory limit.
static_assert(loopsub::Options{}.memory_limit_bytes == 4294967296u, "update kPlanDoc's memory_limit_bytes default");

}  // namespace

// The keyword-only options shared by Plan() and subdivide(), with their defaults.
#define LOOPSUB_OPTION_ARGS                                                                                           \
    py::kw_only(), py::arg("rules") = "hoppe94", py::arg("crease_edges") = py::none(),                               \
        py::arg("crease_sharpness") = py::none(), py::arg("corner_vertices") = py::none(),                           \
        py::arg("corner_sharpness") = py::none(), py::arg("cone_vertices") = py::none(),                             \
        py::arg("crease_threshold") = 0.0, py::arg("boundary") = "edges", py::arg("crease_method") = "uniform",     \
        py::arg("threads") = 1, py::arg("scalar") = false,                                                            \
        py::arg("memory_limit_bytes") = static_cast<long long>(loopsub::Options{}.memory_limit_bytes),                \
        py::arg("limit_surface") = false, py::arg("uv_interpolation") = "corners",                                    \
        py::arg("face_varying_indices") = py::none(), py::arg("hole_triangles") = py::none(),                        \
        py::arg("level_tables") = "auto"

PYBIND11_MODULE(_loopsub, m) {
    m.doc() = kModuleDoc;
    // pybind11's generated signatures would name the array arguments "handle": each docstring starts with a
    // hand-written signature instead, as numpy's own functions do.
    py::options options;
    options.disable_function_signatures();
    py::register_exception_translator(translate_exception);

    py::class_<PyPlan>(m, "Plan", kPlanDoc)
        .def(py::init([](py::handle triangles, long long num_vertices, int levels, std::string rules,
                         py::object crease_edges, py::object crease_sharpness, py::object corner_vertices,
                         py::object corner_sharpness, py::object cone_vertices, double crease_threshold,
                         std::string boundary, std::string crease_method, int threads, bool scalar,
                         long long memory_limit_bytes, bool limit_surface, std::string uv_interpolation,
                         py::object face_varying_indices, py::object hole_triangles, std::string level_tables) {
                 OptionArgs o{rules,          boundary,         crease_method,    crease_edges, crease_sharpness,
                              corner_vertices, corner_sharpness, cone_vertices,   crease_threshold,
                              threads,         scalar,           memory_limit_bytes, limit_surface, uv_interpolation,
                              face_varying_indices, hole_triangles, level_tables};
                 return build_plan(triangles, num_vertices, levels, o);
             }),
             py::arg("triangles"), py::arg("num_vertices"), py::arg("levels") = 1, LOOPSUB_OPTION_ARGS)
        .def("evaluate", &evaluate, kEvaluateDoc, py::arg("values"), py::arg("out") = py::none())
        .def("evaluate_with_normals", &evaluate_with_normals, kNormalsDoc, py::arg("positions"), py::arg("out") = py::none(),
             py::arg("normals") = py::none())
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
        .def_property_readonly("num_face_varying_layers", [](PyPlan& p) { return int(p.layer_values.size()); },
                               "Number of face-varying layers (face_varying_indices given to the Plan).")
        .def_property_readonly("limit_surface", [](PyPlan& p) { return p.plan.options().limit_surface; },
                               "Whether the last level is put on the limit surface.")
        .def_property_readonly("uv_interpolation", [](PyPlan& p) { return kUvInterpolations[int(p.plan.options().face_varying)]; },
                               "How face-varying layers are interpolated (see the Plan's uv_interpolation).")
        .def_property_readonly("level_tables", [](PyPlan& p) { return kLevelTables[int(p.plan.options().level_tables)]; },
                               "The level_tables option the Plan was built with ('auto', 'stored' or 'derived').")
        .def_property_readonly("levels", [](PyPlan& p) { return p.plan.levels(); }, "Levels of subdivision.")
        .def_property_readonly("rules", [](PyPlan& p) { return rules_name(p.plan.options().rules); },
                               "The rule set: 'hoppe94' or 'opensubdiv'.")
        .def_property_readonly("num_input_vertices", [](PyPlan& p) { return p.plan.num_input_vertices(); })
        .def_property_readonly("num_input_triangles", [](PyPlan& p) { return p.num_input_triangles; })
        .def_property_readonly("num_output_vertices", [](PyPlan& p) { return p.plan.num_output_vertices(); })
        .def_property_readonly("num_output_triangles", [](PyPlan& p) { return p.plan.num_output_triangles(); })
        .def_property_readonly("kernel", [](PyPlan& p) { return loopsub::kernel_name(p.plan.kernel()); },
                               "Name of the evaluation kernel in use: 'scalar', 'sse4.1' or 'avx2'.")
        .def_property_readonly("topology_ms", [](PyPlan& p) { return p.plan.topology_ms(); },
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
        .def_property_readonly(
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
            "crease_edges",
            [](py::object self) {
                const auto& v = self.cast<PyPlan&>().plan.output_crease_edges();
                return plan_view(v.data(), {py::ssize_t(v.size() / 2), 2}, self);
            },
            "(K, 2) int32: the output's crease edges (read-only view).")
        .def_property_readonly(
            "crease_sharpness",
            [](py::object self) {
                const auto& v = self.cast<PyPlan&>().plan.output_crease_sharpness();
                return plan_view(v.data(), {py::ssize_t(v.size())}, self);
            },
            "(K,) float32: sharpness of the output's crease edges (read-only view).")
        .def_property_readonly(
            "corner_vertices",
            [](py::object self) {
                const auto& v = self.cast<PyPlan&>().plan.output_corner_vertices();
                return plan_view(v.data(), {py::ssize_t(v.size())}, self);
            },
            "(K,) int32: the output's corner vertices (read-only view).")
        .def_property_readonly(
            "corner_sharpness",
            [](py::object self) {
                const auto& v = self.cast<PyPlan&>().plan.output_corner_sharpness();
                return plan_view(v.data(), {py::ssize_t(v.size())}, self);
            },
            "(K,) float32: sharpness of the output's corner vertices (read-only view).")
        .def_property_readonly(
            "sharp_edges",
            [](py::object self) {
                const auto& v = self.cast<PyPlan&>().plan.output_sharp_edges();
                return plan_view(v.data(), {py::ssize_t(v.size() / 2), 2}, self);
            },
            "(S, 2) int32: every output edge the rules treat as sharp: creases that pass the rules, boundary and "
            "non-manifold edges (read-only view). With level_vertex_types(levels), what to tag the output with.")
        .def_property_readonly(
            "sharp_edge_sharpness",
            [](py::object self) {
                const auto& v = self.cast<PyPlan&>().plan.output_sharp_edge_sharpness();
                return plan_view(v.data(), {py::ssize_t(v.size())}, self);
            },
            "(S,) float32: sharpness of each of sharp_edges (10: infinitely sharp) (read-only view).")
        .def(
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
            "level_edges(level)\n\n(E, 2) int32: the edges of level L; edge k becomes vertex level_num_vertices(L) + k of level L+1.")
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
                                          std::to_string(level) + (p.plan.levels() == 0 ? " (a plan of no levels has no classes)" : ""));
                const auto& v = p.plan.level_vertex_types(level);
                static_assert(sizeof(loopsub::VertexType) == 1, "VertexType is viewed as uint8");
                return plan_view(reinterpret_cast<const std::uint8_t*>(v.data()), {py::ssize_t(v.size())}, self);
            },
            py::arg("level"),
            "level_vertex_types(level)\n\n(N_L,) uint8: the class of each vertex of level L (0 <= L <= levels) as used to "
            "reposition it; for L = levels, the output's classes (as a deeper plan or the limit uses them: what to tag "
            "the result with). Names in VERTEX_TYPES (read-only view).")
        .def("__repr__", [](PyPlan& p) {
            return "<_loopsub.Plan rules=" + std::string(rules_name(p.plan.options().rules)) +
                   " levels=" + std::to_string(p.plan.levels()) + " vertices=" + std::to_string(p.plan.num_input_vertices()) +
                   "->" + std::to_string(p.plan.num_output_vertices()) + " triangles=" +
                   std::to_string(p.num_input_triangles) + "->" + std::to_string(p.plan.num_output_triangles()) + ">";
        });

    m.def(
        "subdivide",
        [](py::handle positions, py::handle triangles, int levels, std::string rules, py::object crease_edges,
           py::object crease_sharpness, py::object corner_vertices, py::object corner_sharpness,
           py::object cone_vertices, double crease_threshold, std::string boundary, std::string crease_method,
           int threads, bool scalar, long long memory_limit_bytes, bool limit_surface, std::string uv_interpolation,
           py::object face_varying_indices, py::object hole_triangles, std::string level_tables, py::handle vertex_data,
           py::handle face_varying) {
            OptionArgs o{rules,          boundary,         crease_method,  crease_edges, crease_sharpness,
                         corner_vertices, corner_sharpness, cone_vertices, crease_threshold,
                         threads,         scalar,           memory_limit_bytes, limit_surface, uv_interpolation,
                         face_varying_indices, hole_triangles, level_tables};
            return subdivide(positions, triangles, levels, o, vertex_data, face_varying);
        },
        kSubdivideDoc, py::arg("positions"), py::arg("triangles"), py::arg("levels") = 1, LOOPSUB_OPTION_ARGS,
        py::arg("vertex_data") = py::none(), py::arg("face_varying") = py::none());

    m.def("best_kernel", [] { return loopsub::kernel_name(loopsub::best_kernel()); },
          "best_kernel()\n\nName of the widest evaluation kernel this CPU runs ('avx2', 'sse4.1' or 'scalar').");

    // Index = the uint8 value of Plan.level_vertex_types() (loopsub::VertexType).
    m.attr("VERTEX_TYPES") = py::make_tuple("smooth", "dart", "regular_crease", "irregular_crease", "corner", "cone");
    m.attr("INFINITE_SHARPNESS") = loopsub::kInfiniteSharpness;
}
