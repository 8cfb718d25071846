#include "problems.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "arguments.h"
#include "plan.h"

namespace loopsub::python {

namespace {

// The exception type, made once by bind_problems (the module lives as long as the interpreter).
PyObject* input_error_type = nullptr;

py::object index_or_none(int value) { return value < 0 ? py::object(py::none()) : py::object(py::int_(value)); }

// The attributes an InputProblem and an InputError share, by name: kind and element as problem_name() spells them,
// the numbers (None where the kind has none), value and limit.
void set_attributes(py::handle target, const loopsub::InputProblem* p) {
    const py::object none = py::none();
    target.attr("kind") = p ? py::object(py::str(loopsub::problem_name(p->kind))) : none;
    target.attr("element") = p ? py::object(py::str(loopsub::problem_name(p->element))) : none;
    target.attr("index") = p ? index_or_none(p->index) : none;
    target.attr("corner") = p ? index_or_none(p->corner) : none;
    // A vertex out of range may be negative itself: refers_to is given as is wherever the kind names one.
    using Kind = loopsub::InputProblem::Kind;
    const bool has_value = p && (p->kind == Kind::BadSharpness || p->kind == Kind::NonFiniteValue ||
                                 p->kind == Kind::ValueTooLarge || p->kind == Kind::RateOutOfRange);
    const bool refers = p && p->kind != Kind::RunsTheSameWay && (!has_value || p->kind == Kind::RateOutOfRange);
    target.attr("refers_to") = refers ? py::object(py::int_(p->refers_to)) : none;
    target.attr("other") = p ? index_or_none(p->other) : none;
    target.attr("layer") = p ? index_or_none(p->layer) : none;
    target.attr("channel") =
        p && p->element != loopsub::InputProblem::Element::Camera ? index_or_none(p->channel) : none;
    target.attr("value") = has_value ? py::object(py::float_(p->value)) : none;
    const bool has_limit = p && (p->kind == Kind::ValueTooLarge || p->kind == Kind::RateOutOfRange);
    target.attr("limit") = has_limit ? py::object(py::float_(p->limit)) : none;
}

// A problem as Python sees it: a plain object with the attributes, its message and whether it is a note.
py::object problem_object(const loopsub::InputProblem& p) {
    py::object object = py::module_::import("types").attr("SimpleNamespace")();
    set_attributes(object, &p);
    object.attr("message") = p.message();
    object.attr("is_note") = p.is_note();
    return object;
}

py::list problem_list(const std::vector<loopsub::InputProblem>& problems) {
    py::list list;
    for (const loopsub::InputProblem& p : problems) list.append(problem_object(p));
    return list;
}

// diagnose(): the mesh read as Plan() reads it, then the core's checks, of the values too where given.
py::list diagnose(py::handle triangles, long long num_vertices, const OptionArgs& args, py::handle positions,
                  py::handle face_varying) {
    PlanInput in;
    read_input(in, triangles, num_vertices, 0, args);
    std::vector<loopsub::InputProblem> problems;
    py::array values;
    loopsub::ChannelsView<const float> vertex_values;
    if (!positions.is_none()) {
        auto [array, channels] = read_vertex_values(positions, "positions", in.mesh.num_vertices);
        values = array;
        vertex_values = loopsub::interleaved(data_of<float>(values), channels);
    }
    {
        py::gil_scoped_release nogil;
        problems = loopsub::diagnose(in.mesh, vertex_values);
    }
    // Per-corner values, each array a layer after the face_varying_indices given, as subdivide() numbers them.
    int layer = in.mesh.num_face_varying;
    auto check_corners = [&](py::handle array, const std::string& name) {
        auto [corners, channels] = read_corner_values(array, name.c_str(), in.mesh.num_triangles);
        const std::vector<loopsub::InputProblem> found =
            loopsub::diagnose_corner_values(data_of<float>(corners), in.mesh.num_triangles, channels, layer++);
        problems.insert(problems.end(), found.begin(), found.end());
    };
    if (py::isinstance<py::dict>(face_varying)) {
        for (auto item : py::reinterpret_borrow<py::dict>(face_varying))
            check_corners(item.second, "face_varying[" + std::string(py::repr(item.first)) + "]");
    } else if (!face_varying.is_none()) {
        check_corners(face_varying, "face_varying");
    }
    return problem_list(problems);
}

constexpr const char* kDiagnoseDoc =
    R"doc(diagnose(triangles, num_vertices, *, <the options of Plan>, positions=None, face_varying=None)

Everything the core would refuse in a mesh, its tags and its values, and what it would tell of it, as a list.

The checks are the ones ``Plan`` and ``subdivide`` make (one implementation in the core); they raise the first
problem as :class:`InputError`, ``diagnose`` lists them all: the holes, the triangles (vertex out of range,
degenerate), the creases, corners and cones (vertex out of range, sharpness negative or not finite), the
face-varying layers' value indices, the creases that are no edge of the mesh (only where the triangles and the
creases' vertices are sound), the non-finite ``positions`` (any per-vertex channels, (N, C) or (N,)) and
``face_varying`` values (per corner, as ``subdivide`` takes them: an array or a dict of them, numbered as layers
after ``face_varying_indices``), then the notes (``is_note``): each edge two triangles run along the same way
(a face wound against its neighbours; the rules make it infinitely sharp), as ``Plan.notes`` gives them.

Each item has the attributes of :class:`InputError` (``kind``, ``element``, ``index``, ``corner``,
``refers_to``, ``other``, ``layer``, ``channel``, ``value``, ``limit``), its ``message`` and ``is_note``.
A value too large to refine depends on the plan's levels and is raised by the evaluation only.
)doc";

constexpr const char* kInputErrorDoc =
    R"doc(Invalid input, raised by the core (a ValueError, so ``except ValueError`` catches it).

Where the data is at fault it says where, in the core's numbering, as attributes (None where they do not apply,
all None where the call itself is at fault, such as a wrong number of channels):

kind : str
    ``"vertex_out_of_range"``, ``"triangle_out_of_range"`` (a hole), ``"value_out_of_range"`` (a face-varying
    layer's value index), ``"degenerate_triangle"``, ``"not_an_edge"`` (a crease, or an edge given a rate),
    ``"bad_sharpness"``, ``"non_finite_value"``, ``"value_too_large"``, ``"rate_out_of_range"`` (a
    ``Tessellation``'s ``edge_rates``) or, as a note of ``diagnose``, ``"runs_the_same_way"``.
element : str
    What ``index`` numbers: ``"vertex"``, ``"triangle"``, ``"crease_edge"``, ``"corner_vertex"``, ``"cone"``,
    ``"hole"``, ``"face_varying_value"``, ``"rated_edge"`` (a row of a ``Tessellation``'s ``edges`` and
    ``edge_rates``) or ``"camera"`` (an entry of ``screen_space_rates``' ``world_to_clip``, row-major).
index, corner : int
    The element, and of a triangle the corner (0-2) where it applies.
refers_to : int
    The vertex, triangle or value the element names (out of range; for a degenerate triangle the repeated vertex;
    for a crease or a rated edge its first vertex).
other : int
    The count the index was out of, the crease's or rated edge's second vertex, or the triangle a note's triangle
    shares its edge with; of ``value_too_large``, how many values a sum adds.
layer, channel : int
    The face-varying layer and the channel of a value.
value, limit : float
    The sharpness, value or rate at fault, and the bound a value too large or a rate passed (a rate's largest,
    4096).
problem : SimpleNamespace or None
    The same attributes with ``message`` and ``is_note``, as ``diagnose`` lists them.
)doc";

}  // namespace

void set_input_error(const loopsub::InputError& error) {
    py::object exception =
        py::reinterpret_steal<py::object>(PyObject_CallFunction(input_error_type, "s", error.what()));
    if (!exception) return;  // PyObject_CallFunction set its own error
    set_attributes(exception, error.problem());
    exception.attr("problem") = error.problem() ? problem_object(*error.problem()) : py::object(py::none());
    PyErr_SetObject(input_error_type, exception.ptr());
}

void bind_problems(py::module_& m) {
    input_error_type = PyErr_NewExceptionWithDoc("_loopsub.InputError", kInputErrorDoc, PyExc_ValueError, nullptr);
    m.add_object("InputError", py::handle(input_error_type));
    m.def(
        "diagnose",
        [](py::handle triangles, long long num_vertices LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_PARAMETER),
           py::handle positions, py::handle face_varying) {
            return diagnose(triangles, num_vertices, OptionArgs{LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_VALUE)},
                            positions, face_varying);
        },
        kDiagnoseDoc, py::arg("triangles"), py::arg("num_vertices"),
        py::kw_only() LOOPSUB_FOR_EACH_OPTION(LOOPSUB_OPTION_ARG), py::arg("positions") = py::none(),
        py::arg("face_varying") = py::none());
}

py::list notes_of(const std::vector<loopsub::InputProblem>& notes) { return problem_list(notes); }

}  // namespace loopsub::python
