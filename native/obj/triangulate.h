// Triangulation of one planar-ish polygon by ear clipping, as Blender's tessellation does it (polyfill): concave
// polygons give triangles inside the polygon, never a fan that folds over itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace loopsub::obj {

// positions: 3 floats per vertex; corners: the polygon's n >= 3 vertex indices in order. Appends n - 2 triangles as
// positions in `corners` (0 .. n-1), winding kept. A convex polygon gives the fan around its first corner.
void triangulate_polygon(const std::vector<float>& positions, const std::vector<std::int32_t>& corners,
                         std::vector<std::size_t>& triangles);

}  // namespace loopsub::obj
