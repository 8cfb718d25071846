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

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
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
    throw py::value_error("boundary must be 'edges' or 'edges-and-corners', got '" + s + "'");
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
    py::array triangles, crease_edges, crease_sharpness, corner_vertices, corner_sharpness, cone_vertices;
    std::vector<float> default_crease_sharpness, default_corner_sharpness;  // when only the tags are given
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
};

void read_input(PlanInput& in, py::handle triangles, long long num_vertices, int levels, const OptionArgs& o) {
    if (levels < 0) throw py::value_error("levels must be >= 0, got " + std::to_string(levels));
    if (num_vertices < 0) throw py::value_error("num_vertices must be >= 0, got " + std::to_string(num_vertices));
    if (o.threads < 1) throw py::value_error("threads must be >= 1, got " + std::to_string(o.threads));
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
}

// ---------------------------------------------------------------------------------------------------------------
// The Plan object

struct PyPlan {
    PyPlan(loopsub::Plan&& p, int triangles) : plan(std::move(p)), num_input_triangles(triangles) {}
    loopsub::Plan plan;
    int num_input_triangles;  // the core does not keep it; face-varying input is checked against it
    // Plan::evaluate is not reentrant (it owns scratch buffers) and runs without the GIL, so two Python threads
    // evaluating one plan must take turns.
    std::mutex evaluate_mutex;
};

std::unique_ptr<PyPlan> build_plan(py::handle triangles, long long num_vertices, int levels, const OptionArgs& args) {
    PlanInput in;
    read_input(in, triangles, num_vertices, levels, args);
    // All Python objects are read: the topology work runs without the GIL. `in` keeps the buffers alive.
    py::gil_scoped_release nogil;
    return std::make_unique<PyPlan>(loopsub::Plan(in.mesh, in.options), in.mesh.num_triangles);
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

py::array evaluate_face_varying(py::object self, py::handle values, py::handle out) {
    PyPlan& p = self.cast<PyPlan&>();
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

    py::object plan = py::cast(build_plan(tris, n, levels, args));
    const py::handle none = py::none();
    auto eval_vertex = [&](py::handle a) { return evaluate(plan, a, none); };
    auto eval_corner = [&](py::handle a) { return evaluate_face_varying(plan, a, none); };

    PyPlan& p = plan.cast<PyPlan&>();
    const py::ssize_t m_out = p.plan.num_output_triangles();
    py::dict r;
    r["positions"] = evaluate(plan, pos, none);
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

constexpr const char* kPlanDoc = R"doc(Plan(triangles, num_vertices, levels=1, *, rules="hoppe94", crease_edges=None, crease_sharpness=None, corner_vertices=None, corner_sharpness=None, cone_vertices=None, crease_threshold=0.0, boundary="edges", crease_method="uniform", threads=1, scalar=False, memory_limit_bytes=4294967296)

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
boundary : {"edges", "edges-and-corners"}, optional
    ``"edges-and-corners"`` makes boundary vertices with a single face corners, under either rule set
    (Blender's "Keep Corners"). Default ``"edges"``: boundary edges are creases.
crease_method : {"uniform", "chaikin"}, optional
    ``"opensubdiv"``: how semi-sharp sharpness decays from level to level.
threads : int, optional
    Threads used by evaluation (1 or 2 on the target machines).
scalar : bool, optional
    Force the scalar reference kernel instead of the widest SIMD one the CPU runs.
memory_limit_bytes : int, optional
    Refuse (``MemoryError``) a refinement that would need more than this (default 4 GiB).

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

constexpr const char* kFaceVaryingDoc = R"doc(evaluate_face_varying(values, out=None)

Refine face-varying data (UVs), linearly within each face.

Parameters
----------
values : numpy.ndarray of float32, shape (T, 3, C) or (T, 3)
    C values per corner of each input triangle, in the corner order of ``triangles``. Must be finite.
out : numpy.ndarray of float32, shape (T_out, 3, C) or (T_out, 3), optional
    Where to write the result. Default: a new array.

Returns
-------
numpy.ndarray of float32, shape (T_out, 3, C) or (T_out, 3)
    Values per corner of each output triangle, in the corner order of ``Plan.triangles``.
    Seams stay seams: each output corner depends only on its parent face's values.
)doc";

constexpr const char* kSubdivideDoc = R"doc(subdivide(positions, triangles, levels=1, *, <the options of Plan>, vertex_data=None, face_varying=None)

Subdivide a mesh in one call (builds a Plan and evaluates it).

Parameters
----------
positions : numpy.ndarray of float32, shape (N, 3)
triangles : numpy.ndarray of int32, shape (M, 3)
levels : int, optional
    Default 1.
rules, crease_edges, crease_sharpness, corner_vertices, corner_sharpness, cone_vertices, crease_threshold, boundary, crease_method, threads, scalar, memory_limit_bytes
    As for :class:`Plan`.
vertex_data : numpy.ndarray of float32, shape (N, C) or (N,), or dict of them, optional
    Other per-vertex channels, refined with the same weights as the positions.
face_varying : numpy.ndarray of float32, shape (M, 3, C) or (M, 3), or dict of them, optional
    Per-corner data (UVs), refined linearly within each face.

Returns
-------
dict
    ``positions`` (N_out, 3) float32; ``triangles`` (M_out, 3) int32; ``parent_triangles`` (M_out,) int32
    (index of the input triangle each output triangle comes from); ``crease_edges`` (K, 2) int32 and
    ``crease_sharpness`` (K,) float32, ``corner_vertices`` and ``corner_sharpness``: the output's tags, ready
    to be fed back in; ``vertex_data`` and ``face_varying``: refined like the arguments (an array, a dict with the
    same keys, or None); ``plan``: the :class:`Plan`, to re-evaluate new positions on the same topology.
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
        py::arg("memory_limit_bytes") = static_cast<long long>(loopsub::Options{}.memory_limit_bytes)

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
                         long long memory_limit_bytes) {
                 OptionArgs o{rules,          boundary,         crease_method,    crease_edges, crease_sharpness,
                              corner_vertices, corner_sharpness, cone_vertices,   crease_threshold,
                              threads,         scalar,           memory_limit_bytes};
                 return build_plan(triangles, num_vertices, levels, o);
             }),
             py::arg("triangles"), py::arg("num_vertices"), py::arg("levels") = 1, LOOPSUB_OPTION_ARGS)
        .def("evaluate", &evaluate, kEvaluateDoc, py::arg("values"), py::arg("out") = py::none())
        .def("evaluate_face_varying", &evaluate_face_varying, kFaceVaryingDoc, py::arg("values"),
             py::arg("out") = py::none())
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
                if (level < 0 || level >= p.plan.levels())
                    throw py::index_error("level must be in [0, " + std::to_string(p.plan.levels()) + "), got " +
                                          std::to_string(level));
                const auto& v = p.plan.level_vertex_types(level);
                static_assert(sizeof(loopsub::VertexType) == 1, "VertexType is viewed as uint8");
                return plan_view(reinterpret_cast<const std::uint8_t*>(v.data()), {py::ssize_t(v.size())}, self);
            },
            py::arg("level"),
            "level_vertex_types(level)\n\n(N_L,) uint8: the class of each vertex of level L as used to reposition it; "
            "names in VERTEX_TYPES (read-only view).")
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
           int threads, bool scalar, long long memory_limit_bytes, py::handle vertex_data, py::handle face_varying) {
            OptionArgs o{rules,          boundary,         crease_method,  crease_edges, crease_sharpness,
                         corner_vertices, corner_sharpness, cone_vertices, crease_threshold,
                         threads,         scalar,           memory_limit_bytes};
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
