#include "arguments.h"

#include <cstdint>
#include <limits>
#include <sstream>

namespace loopsub::python {

std::string describe_shape(const std::vector<Dim>& dims) {
    std::ostringstream s;
    s << '(';
    for (std::size_t i = 0; i < dims.size(); ++i) {
        if (i) s << ", ";
        if (dims[i].size < 0) s << dims[i].symbol;
        else if (dims[i].symbol[0] >= '0' && dims[i].symbol[0] <= '9')
            s << dims[i].size;  // a literal such as the 3 of (M, 3)
        else s << dims[i].symbol << '=' << dims[i].size;
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

void require_layout(const py::array& a, const char* name, bool writeable) {
    if (!(a.flags() & py::array::c_style))
        throw py::value_error(std::string(name) + " must be C-contiguous, got a strided array of shape " +
                              actual_shape(a) + " (use numpy.ascontiguousarray(" + name + "))");
    if (!(a.flags() & py::detail::npy_api::NPY_ARRAY_ALIGNED_))
        throw py::value_error(std::string(name) + " must be aligned to its dtype, got an unaligned buffer");
    if (writeable && !a.writeable())
        throw py::value_error(std::string(name) + " must be writeable, got a read-only array");
}

int checked_count(long long n, const char* what) {
    if (n > std::numeric_limits<int>::max())
        throw py::value_error(std::string(what) + " " + std::to_string(n) + " exceeds the supported maximum " +
                              std::to_string(std::numeric_limits<int>::max()));
    return int(n);
}

bool overlaps(const py::array& a, const py::array& b) {
    auto lo_a = reinterpret_cast<std::uintptr_t>(a.data()), lo_b = reinterpret_cast<std::uintptr_t>(b.data());
    auto hi_a = lo_a + std::uintptr_t(a.nbytes()), hi_b = lo_b + std::uintptr_t(b.nbytes());
    return a.nbytes() > 0 && b.nbytes() > 0 && lo_a < hi_b && lo_b < hi_a;
}

std::pair<py::array, int> read_vertex_values(py::handle values, const char* name, int num_vertices) {
    py::array a = require_dtype<float>(values, name);
    const bool ok = (a.ndim() == 1 || a.ndim() == 2) && a.shape(0) == num_vertices;
    if (!ok)
        throw py::value_error(std::string(name) + " must have shape (N=" + std::to_string(num_vertices) +
                              ", C) or (N=" + std::to_string(num_vertices) + ",), got " + actual_shape(a));
    require_layout(a, name, false);
    return {a, a.ndim() == 2 ? checked_count(a.shape(1), "number of channels") : 1};
}

std::pair<py::array, int> read_corner_values(py::handle values, const char* name, int num_triangles) {
    py::array a = require_dtype<float>(values, name);
    const bool ok = (a.ndim() == 2 || a.ndim() == 3) && a.shape(0) == num_triangles && a.shape(1) == 3;
    if (!ok)
        throw py::value_error(std::string(name) + " must have shape (T=" + std::to_string(num_triangles) +
                              ", 3, C) or (T=" + std::to_string(num_triangles) + ", 3), got " + actual_shape(a));
    require_layout(a, name, false);
    return {a, a.ndim() == 3 ? checked_count(a.shape(2), "number of channels") : 1};
}

py::array output_array(py::handle out, const std::vector<Dim>& dims, const py::array& input) {
    if (out.is_none()) {
        std::vector<py::ssize_t> shape;
        for (const Dim& d : dims) shape.push_back(d.size);
        return new_array<float>(shape);
    }
    py::array a = require_array<float>(out, "out", dims, /*writeable=*/true);
    if (overlaps(a, input)) throw py::value_error("out must not share memory with the input values");
    return a;
}

py::array new_array(const py::dtype& dtype, std::size_t item_size, const std::vector<py::ssize_t>& shape) {
    std::size_t bytes = item_size;
    for (py::ssize_t n : shape) bytes *= std::size_t(n);
    struct Memory {
        void* data;
        std::size_t bytes;
    };
    void (*release)(void*) = [](void* m) {
        auto* memory = static_cast<Memory*>(m);
        loopsub::free_array_memory(memory->data, memory->bytes);
        delete memory;
    };
    auto* memory = new Memory{nullptr, bytes};
    py::capsule owner;
    try {
        memory->data = loopsub::allocate_array_memory(bytes);
        owner = py::capsule(memory, release);
    } catch (...) {
        release(memory);  // free_array_memory takes null
        throw;
    }
    std::vector<py::ssize_t> strides(shape.size());
    py::ssize_t stride = py::ssize_t(item_size);
    for (std::size_t k = shape.size(); k-- > 0;) {
        strides[k] = stride;
        stride *= shape[k];
    }
    return py::array(dtype, shape, strides, memory->data, owner);
}

}  // namespace loopsub::python
