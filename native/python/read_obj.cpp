#include "read_obj.h"

#include <pybind11/numpy.h>

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "arguments.h"
#include "obj/obj_io.h"

namespace loopsub::python {

namespace py = pybind11;

namespace {

// An option a tag set, by the name Plan's keyword takes; None where the file has no such tag.
template <typename Option>
py::object name_or_none(const std::optional<Option>& value) {
    return value ? py::object(py::str(loopsub::option_name(*value))) : py::object(py::none());
}

py::dict read_obj(const std::string& path) {
    loopsub::obj::ObjMesh mesh;
    {
        py::gil_scoped_release nogil;
        mesh = loopsub::obj::read_obj(path);
    }
    py::dict out;
    out["positions"] = rows(mesh.positions, 3);
    out["triangles"] = rows(mesh.triangles, 3);
    out["crease_edges"] = rows(mesh.crease_edges, 2);
    out["crease_sharpness"] = rows(mesh.crease_sharpness);
    out["corner_vertices"] = rows(mesh.corner_vertices);
    out["corner_sharpness"] = rows(mesh.corner_sharpness);
    out["cone_vertices"] = rows(mesh.cone_vertices);
    out["hole_triangles"] = rows(mesh.hole_triangles);
    out["boundary"] = name_or_none(mesh.boundary);
    out["crease_method"] = name_or_none(mesh.crease_method);
    out["uv_interpolation"] = name_or_none(mesh.face_varying);
    return out;
}

constexpr const char* kReadObjDoc = R"doc(read_obj(path)

An OBJ file read as the ``loopsub`` command reads it (docs/cli.md, "What it reads"): its mesh, polygons split into
triangles, and OpenSubdiv's tags, 0-based. Returns a dict of new arrays: ``positions`` (N, 3) float32,
``triangles`` (M, 3) int32, ``crease_edges`` (K, 2) int32 with ``crease_sharpness`` (K,) float32,
``corner_vertices`` with ``corner_sharpness``, ``cone_vertices``, ``hole_triangles``; and the rules the file's tags
set, by the names Plan's keywords take, or None: ``boundary`` (``t interpolateboundary``), ``crease_method``
(``t creasemethod``), ``uv_interpolation`` (``t facevaryinginterpolateboundary``). Raises InputError naming the
file and line for anything it cannot read; a tag's vertex out of range is the core's to find (Plan, diagnose).
)doc";

}  // namespace

void bind_obj(py::module_& m) { m.def("read_obj", &read_obj, kReadObjDoc, py::arg("path")); }

}  // namespace loopsub::python
