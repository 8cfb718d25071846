#include "triangulate.h"

#include <array>
#include <cmath>

namespace loopsub::obj {

namespace {

using Point = std::array<double, 2>;

double cross(const Point& o, const Point& a, const Point& b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

// Inside or on the border of the counter-clockwise triangle abc.
bool in_triangle(const Point& p, const Point& a, const Point& b, const Point& c) {
    return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
}

}  // namespace

void triangulate_polygon(const std::vector<float>& positions, const std::vector<std::int32_t>& corners,
                         std::vector<std::size_t>& triangles) {
    const std::size_t n = corners.size();
    // The polygon's plane from Newell's normal; the projection drops the normal's largest axis and keeps the
    // polygon counter-clockwise.
    double normal[3] = {0.0, 0.0, 0.0};
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &positions[3 * std::size_t(corners[i])];
        const float* q = &positions[3 * std::size_t(corners[(i + 1) % n])];
        for (int axis = 0; axis < 3; ++axis) {
            const int u = (axis + 1) % 3, v = (axis + 2) % 3;
            normal[axis] += (double(p[u]) - q[u]) * (double(p[v]) + q[v]);
        }
    }
    int drop = 0;
    for (int axis = 1; axis < 3; ++axis)
        if (std::fabs(normal[axis]) > std::fabs(normal[drop])) drop = axis;
    const int u = (drop + 1) % 3, v = (drop + 2) % 3;
    const double flip = normal[drop] < 0.0 ? -1.0 : 1.0;
    std::vector<Point> points(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &positions[3 * std::size_t(corners[i])];
        points[i] = {p[u], flip * p[v]};
    }

    std::vector<std::size_t> remaining(n);
    for (std::size_t i = 0; i < n; ++i) remaining[i] = i;
    // Ears are sought from the second corner on, so that a convex polygon gives the fan around its first corner.
    std::size_t at = 1;
    while (remaining.size() > 3) {
        const std::size_t m = remaining.size();
        bool clipped = false;
        for (std::size_t tried = 0; tried < m && !clipped; ++tried) {
            const std::size_t k = (at + tried) % m;
            const std::size_t a = remaining[(k + m - 1) % m], b = remaining[k], c = remaining[(k + 1) % m];
            if (cross(points[a], points[b], points[c]) <= 0.0) continue;  // reflex or flat: not an ear
            bool empty = true;
            for (std::size_t j : remaining) {
                // A polygon around a hole visits the vertices of its bridge twice: those copies are the ear's own.
                const std::int32_t vertex = corners[j];
                if (vertex != corners[a] && vertex != corners[b] && vertex != corners[c] &&
                    in_triangle(points[j], points[a], points[b], points[c])) {
                    empty = false;
                    break;
                }
            }
            if (!empty) continue;
            triangles.insert(triangles.end(), {a, b, c});
            remaining.erase(remaining.begin() + std::ptrdiff_t(k));
            at = k % remaining.size();
            clipped = true;
        }
        if (!clipped) {
            // No ear: a self-intersecting or degenerate polygon. Clip where the search stands, so that the result
            // still has n - 2 triangles covering the corners.
            const std::size_t k = at % m;
            triangles.insert(triangles.end(), {remaining[(k + m - 1) % m], remaining[k], remaining[(k + 1) % m]});
            remaining.erase(remaining.begin() + std::ptrdiff_t(k));
            at = k % remaining.size();
        }
    }
    triangles.insert(triangles.end(), {remaining[0], remaining[1], remaining[2]});
}

}  // namespace loopsub::obj
