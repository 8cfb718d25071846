// What the face-varying builder's files (face_varying*.cpp) share: a level's values grouped by vertex, and arrays
// copied and joined in parts on the plan's threads.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "base/large_allocator.h"
#include "base/parallel.h"
#include "rules/rules.h"
#include "tables/stencils.h"

namespace loopsub::detail {

// The items (values or corners) of each vertex, in item order, as offsets into one list (CSR), from each item's vertex:
// a counting sort. In parts, each counts its own items, then places them after those of the parts before it, so that a
// vertex's items stay in item order whatever the number of parts.
void group_by_vertex(const Index* vertex_of, std::size_t items, int num_vertices, TransientVector<Index>& offsets,
                     TransientVector<Index>& grouped, int parts = 1);

// A copy of `from`, in parts.
LargeVector<Index> copy_in_parts(const LargeVector<Index>& from, int parts);

// The parts' lists one after the other, copied in parts where they are long (short lists, the usual masks, are not
// worth a meeting of the parts).
template <typename T, typename Parts, typename List>
void join_in_parts(const Parts& parts, List list, std::vector<T>& joined) {
    std::vector<std::size_t> starts(parts.size() + 1, 0);
    for (std::size_t p = 0; p < parts.size(); ++p) starts[p + 1] = starts[p] + list(parts[p]).size();
    joined.resize(starts.back());
    auto copy = [&](std::size_t part) {
        std::copy(list(parts[part]).begin(), list(parts[part]).end(), joined.begin() + std::ptrdiff_t(starts[part]));
    };
    if (starts.back() < 8192) {
        for (std::size_t part = 0; part < parts.size(); ++part) copy(part);
        return;
    }
    run_levels(int(parts.size()), 1, [&](int, int part, int) { copy(std::size_t(part)); });
}

// A value that stays where it is: the corner mask.
inline SpecialVertex staying_value(Index x) {
    const VertexMask corner = corner_vertex_mask();
    return {x, x, x, float(corner.self), float(corner.ring), float(corner.crease), float(corner.crease)};
}

}  // namespace loopsub::detail
