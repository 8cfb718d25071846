// The corners of a triangle, 0 1 2 counter-clockwise; edge k runs from corner k to the next.
#pragma once

namespace loopsub::detail {

inline int next_corner(int corner) { return corner == 2 ? 0 : corner + 1; }
inline int prev_corner(int corner) { return corner == 0 ? 2 : corner - 1; }

}  // namespace loopsub::detail
