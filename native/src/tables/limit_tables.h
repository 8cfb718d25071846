// The limit surface's tables (Options::limit_surface): what PlanBuilder::plan_limit (plan/limit.cpp) writes and the
// limit kernels (kernels.h, LimitFn; kernels/limit_normals.h) read every frame.
#pragma once

#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "tables/stencils.h"

namespace loopsub::detail {

// One more vertex-only pass over the last level, and the tables of the limit normals.
struct LimitTables {
    // Limit positions: the kernels' vertex masks (num_edges == 0). Where a vertex's fan is a disk of smooth edges
    // its ring is in counter-clockwise order, as the smooth tangent masks read it.
    LevelStencils positions;
    // Vertices whose normals are their sides' (crease and corner rules, boundaries, or a fan that is not a disk): 1
    // per such vertex.
    LargeVector<std::uint8_t> by_side;
    // A side: `faces` faces counter-clockwise around `vertex`, through points side_points[first ..]: faces + 1 of
    // them from the leading to the trailing sharp edge, or `faces` of them for a closed fan. Its normal goes to row
    // `row` of the compact normals (Plan::LimitNormals): its vertex's own where it is the vertex's only side (an open
    // fan, as at a boundary: nothing parts it), else a row of its own past the vertices'.
    struct Side {
        Index vertex, first;
        int faces;
        bool closed;
        // At a corner the vertex stays and each sharp edge's limit curve leaves it along the edge: an open side's
        // tangents are its two sharp edges (OpenSubdiv's corner masks), not the crease's.
        bool corner;
        Index own;  // where its tangent weights are its own (own_t1 / _t2, one per point), else -1
        Index row;
    };
    std::vector<Side> sides;
    std::vector<Index> side_points;
    int num_side_rows = 0;  // the sides with rows of their own
    // The corners that take a side's row of its own: (output corner 3 t + k, row), in the order of their vertices. The
    // others take their vertex's, so the plan keeps no index per corner (Plan::corner_normal_indices makes them on a
    // first request).
    std::vector<std::pair<Index, Index>> corner_sides;
    // Tangent weights: smooth by valence (p_0 .. p_{n-1}), sides by face count (vertex, p_0 .. p_faces).
    std::vector<std::vector<float>> smooth_t1, smooth_t2, side_t1, side_t2;
    // Valence 6 (nearly every vertex): the smooth tangent masks are symmetric, t1 = a (p0 - p3) + b (p1 - p2) +
    // b (p5 - p4) and t2 = c (p1 - p4) + c (p2 - p5) over the ring's points; {a, b, c}, where the plan has valence 6.
    // A third of the masks' arithmetic, and differences of neighbours are as small as their offsets from the vertex.
    float regular_tangents[3] = {0.0f, 0.0f, 0.0f};
    // Where semi-sharp features outlast the last level, the tangent masks that apply once they are spent, pulled back
    // to the last level: weights per point of a vertex's ring (own_vertex_tangents: (vertex, first), sorted) or of a
    // side (Side::own). Their vertex's weight is what the points' leave, as in the tables above.
    std::vector<float> own_t1, own_t2;
    std::vector<std::pair<Index, Index>> own_vertex_tangents;

    // A closed surface without features (PlanBuilder::plan_limit_rings): the last level's rings come from the level
    // two before it, `grandparent`. positions.ring and ring_offsets hold those of its vertices only (the last level's
    // first ones); the others' are written a chunk at a time as the limit pass runs (limit_part,
    // write_ordered_grandchild_rings), the same rings as stored ones, from the grandparent's sides of each edge and
    // halves at each corner (kept here) and its edge ends (its own tables'). Null: every ring is stored.
    struct FromGrandparent {
        Grandparent grandparent;
        LargeVector<Index> edge_sides, corner_halves;
        int max_valence = 0;  // the last level's
        // Past the grandparent's vertices, sorted: those next to tags, whose masks, tangents or sides are their own
        // (what the SIMD kernels' pass by kind leaves to their LimitFn).
        std::vector<Index> redone;
    };
    std::unique_ptr<FromGrandparent> from_grandparent;
};

// Last-level vertex v's ring as the limit pass reads it (counter-clockwise where its fan is a disk): stored, or past
// the grandparent's vertices (LimitTables::from_grandparent) written into `buffer`.
struct LimitRing {
    const Index* ring;
    int count;
};
inline LimitRing limit_ring(const LimitTables& lt, Index v, Index buffer[6]) {
    const LevelStencils& s = lt.positions;
    if (lt.from_grandparent && v >= lt.from_grandparent->grandparent.num_vertices) {
        Index offsets[2];
        write_ordered_grandchild_rings(lt.from_grandparent->grandparent, v, v + 1, offsets, buffer);
        return {buffer, int(offsets[1])};
    }
    return {s.ring.data() + s.ring_offsets[v], int(s.ring_offsets[v + 1] - s.ring_offsets[v])};
}

}  // namespace loopsub::detail
