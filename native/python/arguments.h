// Checks of the arrays handed to the module. Every array must already be a numpy array of exactly the right dtype
// (float32 / int32), C-contiguous, aligned and of the right shape; it is then read in place. A wrong dtype raises
// TypeError, a wrong shape or layout ValueError, each naming the argument, what was expected and what was given.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "loopsub/loopsub.h"

namespace loopsub::python {

namespace py = pybind11;

template <typename T>
const char* dtype_name();
template <>
inline const char* dtype_name<float>() {
    return "float32";
}
template <>
inline const char* dtype_name<std::int32_t>() {
    return "int32";
}

// One expected dimension: a fixed size, or any size (size < 0) shown by its symbol.
struct Dim {
    py::ssize_t size;
    const char* symbol;
};

std::string describe_shape(const std::vector<Dim>& dims);
std::string actual_shape(const py::array& a);
bool shape_matches(const py::array& a, const std::vector<Dim>& dims);

// The core reads the data as a flat T array: it must be C-contiguous and aligned (and writeable for outputs).
void require_layout(const py::array& a, const char* name, bool writeable);

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

template <typename T>
py::array require_array(py::handle obj, const char* name, const std::vector<Dim>& dims, bool writeable = false) {
    py::array a = require_dtype<T>(obj, name);
    if (!shape_matches(a, dims))
        throw py::value_error(std::string(name) + " must have shape " + describe_shape(dims) + ", got " +
                              actual_shape(a));
    require_layout(a, name, writeable);
    return a;
}

// The core counts in int: larger inputs are refused rather than truncated.
int checked_count(long long n, const char* what);

template <typename T>
const T* data_of(const py::array& a) {
    return static_cast<const T*>(a.data());
}

// A new C-contiguous array of `shape`, uninitialised, in the memory of loopsub::allocate_array_memory, which the array
// owns and gives back when it is freed. numpy's own memory would fault in every 4 KiB of a first call's result below
// 4 MiB, and be mapped anew on every call where malloc's thresholds say so (a tessellation's 7.8 MB points and
// normals: 1,600 faults a warm call). The item size and strides are the caller's: pybind11 2.10 reads a dtype's size
// in numpy 1's layout, 0 under numpy 2.
py::array new_array(const py::dtype& dtype, std::size_t item_size, const std::vector<py::ssize_t>& shape);
template <typename T>
py::array new_array(const std::vector<py::ssize_t>& shape) {
    return new_array(py::dtype::of<T>(), sizeof(T), shape);
}

// A new array of `values`, `width` to a row ((N, width); (N,) for 1).
template <typename T>
py::array rows(const std::vector<T>& values, py::ssize_t width = 1) {
    const py::ssize_t n = py::ssize_t(values.size()) / width;
    py::array a = width > 1 ? new_array<T>({n, width}) : new_array<T>({n});
    std::copy(values.begin(), values.end(), static_cast<T*>(a.mutable_data()));
    return a;
}

// Writing the output over the input would read already-overwritten values mid-evaluation.
bool overlaps(const py::array& a, const py::array& b);

// Values per vertex: (N, C), or (N,) for one channel. Returns the checked array and C.
std::pair<py::array, int> read_vertex_values(py::handle values, const char* name, int num_vertices);

// Values per triangle corner: (T, 3, C), or (T, 3) for one channel.
std::pair<py::array, int> read_corner_values(py::handle values, const char* name, int num_triangles);

// One of the option's names (loopsub::option_names), given as the keyword argument `keyword`; ValueError listing
// them otherwise.
template <typename Option>
Option parse_name(const char* keyword, const std::string& text) {
    Option value{};
    if (!loopsub::parse_option(text, value))
        throw py::value_error(std::string(keyword) + " must be " + loopsub::option_names<Option>().listed("'") +
                              ", got '" + text + "'");
    return value;
}

// The output array: `out` checked against the expected shape, or a new uninitialised array of that shape.
py::array output_array(py::handle out, const std::vector<Dim>& dims, const py::array& input);

}  // namespace loopsub::python
