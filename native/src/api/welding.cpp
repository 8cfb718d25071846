// Per-corner values welded into shared ones: the one implementation the CLI (normals), the Python module (UVs read
// per corner) and the add-on use.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

#include "base/input_checks.h"
#include "loopsub/loopsub.h"

namespace loopsub {

namespace {

// Equal bit for bit, or zeros of either sign: -0.0 and 0.0 are the same number, and no seam.
bool same_value(const float* a, const float* b, std::size_t num_channels) {
    for (std::size_t k = 0; k < num_channels; ++k) {
        std::uint32_t x, y;
        std::memcpy(&x, a + k, sizeof x);
        std::memcpy(&y, b + k, sizeof y);
        if (x != y && ((x | y) & 0x7fffffffu) != 0) return false;
    }
    return true;
}

}  // namespace

int weld_corner_values(std::int32_t* corner_value_indices, const std::int32_t* triangles, int num_triangles,
                       int num_vertices, const float* corner_values, int num_channels) {
    if (num_triangles < 0 || num_vertices < 0 || num_channels < 0)
        throw InputError("weld_corner_values: negative count (" + std::to_string(num_triangles) + " triangles, " +
                         std::to_string(num_vertices) + " vertices, " + std::to_string(num_channels) + " channels)");
    const std::size_t num_corners = 3 * std::size_t(num_triangles), width = std::size_t(num_channels);
    if (num_corners > std::size_t(std::numeric_limits<std::int32_t>::max()))
        throw InputError("weld_corner_values: " + std::to_string(num_corners) +
                         " corners are more than 32-bit indices can number");

    // Vertex indices in range: the counting sort below relies on them.
    detail::check_triangles(triangles, num_triangles, num_vertices, false, detail::ThrowFirst{});

    // The corners grouped by vertex, each vertex's in corner order (a counting sort).
    std::vector<std::int32_t> vertex_start(std::size_t(num_vertices) + 1, 0);
    for (std::size_t c = 0; c < num_corners; ++c) ++vertex_start[std::size_t(triangles[c]) + 1];
    std::partial_sum(vertex_start.begin(), vertex_start.end(), vertex_start.begin());
    std::vector<std::int32_t> corners_by_vertex(num_corners);
    {
        std::vector<std::int32_t> next(vertex_start.begin(), vertex_start.end() - 1);
        for (std::size_t c = 0; c < num_corners; ++c)
            corners_by_vertex[std::size_t(next[std::size_t(triangles[c])]++)] = std::int32_t(c);
    }

    // A vertex has a few values at most: each corner is compared with the first corner of each value found so far.
    std::int32_t num_values = 0;
    std::vector<std::int32_t> first_corners;  // of the current vertex's values
    for (std::size_t v = 0; v < std::size_t(num_vertices); ++v) {
        first_corners.clear();
        for (std::int32_t i = vertex_start[v]; i < vertex_start[v + 1]; ++i) {
            const std::int32_t corner = corners_by_vertex[std::size_t(i)];
            const float* value = corner_values + width * std::size_t(corner);
            std::size_t k = 0;
            while (k < first_corners.size() &&
                   !same_value(value, corner_values + width * std::size_t(first_corners[k]), width))
                ++k;
            if (k == first_corners.size()) first_corners.push_back(corner);
            corner_value_indices[corner] = num_values + std::int32_t(k);
        }
        num_values += std::int32_t(first_corners.size());
    }
    return num_values;
}

void gather_welded_values(float* values, const std::int32_t* corner_value_indices, int num_triangles,
                          const float* corner_values, int num_channels) {
    const std::size_t width = std::size_t(std::max(num_channels, 0));
    // From the last corner to the first, so that each value is left with its first corner's (its corners' values
    // differ at most in the sign of a zero).
    for (std::size_t c = 3 * std::size_t(std::max(num_triangles, 0)); c-- > 0;)
        std::copy_n(corner_values + width * c, width, values + width * std::size_t(corner_value_indices[c]));
}

}  // namespace loopsub
