// The per-level stencil tables: what the per-frame kernels read besides the vertex data (stored, or derived from the
// parent level as they run).
//
// Every Loop mask in both rule sets has the same shape, which keeps the kernels branch-free:
//   vertex point  v' = w_self * v + w_ring * (sum of the one-ring) + w_crease_a * p + w_crease_b * q
//   edge point    e' = wa * A + wb * B + wcd * (C + D)
// (smooth, dart, crease, corner and cone masks, the {5,3} and {1,1} edge masks, and OpenSubdiv's blends of two
// of them are all of this form). Most vertices and edges are smooth, so a kernel first applies the smooth mask
// to every vertex and edge of its range (weights by valence from a small table) and then overwrites the few
// special ones from short sorted lists. The one exception is the limit of a vertex whose semi-sharp features outlast
// the last level, a weight per neighbour (RingWeightedVertex).
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "base/large_allocator.h"
#include "rules/rules.h"
#include "topology/topology.h"

namespace loopsub::detail {

struct SpecialVertex {
    std::int32_t vertex;
    std::int32_t crease_a, crease_b;  // the two crease neighbours (any valid index where their weight is 0)
    // Refinement weights p and q alike; the limit of a Hoppe94 crease vertex next to an irregular one does not.
    float w_self, w_ring, w_crease_a, w_crease_b;
};

// A mask with a weight of its own per neighbour: the limit of a vertex whose semi-sharp features outlast the last
// level (limit.cpp). Its weights are ring_weights[first ..], one per neighbour in the order of its ring.
struct RingWeightedVertex {
    std::int32_t vertex;
    std::int32_t first;
    float w_self;
};

struct SpecialEdge {
    std::int32_t edge;
    float wa, wb, wcd;
};

// A level's tables (one per level of a plan, then the limit's pass; a face-varying layer has its own). They take one of
// four forms, which the plan builder chooses (PlanBuilder::choose_table_forms and hand_over_tables; how their speed and
// memory compare: docs/benchmark.md, "Stored or derived tables"; docs/architecture.md, "Level tables"):
//   stored    ring_offsets, ring, edge_ends and edge_wing_c / _d hold every vertex and edge. The base level's; the
//             limit pass's (or its first vertices' only, where the rest come from the grandparent:
//             LimitTables::from_grandparent); the built levels of a face-varying layer.
//   fans      stored, with fan_first_midpoint / fan_midpoints set: the midpoints' rings are laid out so that the fan
//             kernels compute a midpoint and its two halves from one fan of loads. Every stored level of the vertex
//             plan past the base.
//   interior  fans, with the edges inside the parent's faces read from those faces (`interior`) rather than stored: a
//             level that is not built, whose tables are filled from its parent (fill_tables_from_parent) with the
//             last level's triangles beside them. The level before the last where the builder skips it
//             (skip_level_before_last_: two levels or more, no limit surface or one from the grandparent), in the
//             vertex plan unless its tables are derived, and in a face-varying layer unless the layer is linear
//             everywhere.
//   derived   nothing stored but the parent level's connectivity (`derived_from`): the kernels derive the tables a
//             chunk at a time as they run. Every level of the vertex plan past the base where the builder derives
//             tables (derive_tables_: Options::level_tables Derived, or Auto past 128 MiB of stored tables of the
//             level before the last; only where that level is skipped and there is no face-varying layer).
// The special masks (special_vertices, special_edges) and the smooth masks by valence are stored in every form.
struct LevelStencils {
    int num_vertices = 0;  // of this level; output vertex i < num_vertices is vertex i repositioned
    int num_edges = 0;     // output vertex num_vertices + e is edge e bisected

    // One-rings in CSR form: neighbours of vertex i are ring[ring_offsets[i] .. ring_offsets[i + 1]).
    LargeVector<std::int32_t> ring_offsets;
    LargeVector<std::int32_t> ring;
    // Smooth mask by valence n: w_self = smooth_self[n], w_ring = smooth_ring[n] (n = 0: copy the vertex).
    std::vector<float> smooth_self;
    std::vector<float> smooth_ring;
    std::vector<SpecialVertex> special_vertices;             // sorted by vertex
    std::vector<RingWeightedVertex> ring_weighted_vertices;  // sorted by vertex; limit passes only
    std::vector<float> ring_weights;

    // Edge points: the endpoints A, B (pairs: the level's own edge list, taken over rather than copied) and the wings
    // C, D, the vertices opposite the edge in its first two faces (one array each). Where a face is missing, C / D
    // repeat A / B (the edge is then special, with wcd == 0, so the smooth pass's value is overwritten).
    LargeVector<std::int32_t> edge_ends;  // 2 per edge: A, B
    LargeVector<std::int32_t> edge_wing_c, edge_wing_d;
    std::vector<SpecialEdge> special_edges;  // sorted by edge

    // Form "interior": the edges inside the parent's faces, read from the faces. Edge first_edge + 3f + k joins the
    // midpoints of parent face f's edges k and k + 1, opposite the face's corner k + 1 and the midpoint of its edge
    // k - 1 (the vertex of parent edge e is parent_vertices + e). Then edge_ends, edge_wing_c and edge_wing_d hold the
    // edges before first_edge only: a kernel reads three edges' ends and wings from six indices rather than twelve,
    // and the plan writes none of them.
    struct InteriorFaces {
        int first_edge = 0;
        std::int32_t parent_vertices = 0;
        LargeVector<std::int32_t> face_vertices, face_edges;  // the parent's, 3 per face

        // Ends and wings of edge e (first_edge or later).
        void edge(int e, std::int32_t abcd[4]) const {
            const std::size_t face = std::size_t(e - first_edge) / 3;
            face_interior_edge(parent_vertices, &face_vertices[3 * face], &face_edges[3 * face], (e - first_edge) % 3,
                               abcd);
        }
    };
    std::unique_ptr<InteriorFaces> interior;

    // Forms "fans" and "interior": its vertices from fan_first_midpoint on are the midpoints of its parent's
    // fan_midpoints edges (edge e's is fan_first_midpoint + e), its edges 2e and 2e + 1 the halves of parent edge e,
    // and a midpoint's ring is its edge's ends, then its halves' wings face by face (refine_topology,
    // fill_tables_from_parent): a kernel computes the midpoint and both halves from it (FanFn, kernels.h).
    int fan_first_midpoint = 0, fan_midpoints = 0;

    // Form "derived": the level's rings and edges are derived from its parent level's connectivity through the
    // numbering, a chunk at a time as the kernels run (write_child_rings, child_edges, in refine_part). The plan then
    // holds connectivity only.
    std::unique_ptr<Topology> derived_from;

    // The ends of edge e wherever the level keeps them: its tables, its parent's faces (interior) or its parent's
    // connectivity (derived_from). For what asks for a few edges outside the kernels.
    void edge_ends_of(std::int32_t e, std::int32_t ends[2]) const {
        if (derived_from) return child_edge_ends(*derived_from, e, ends);
        if (interior && e >= interior->first_edge) {
            std::int32_t abcd[4];
            interior->edge(e, abcd);
            ends[0] = abcd[0], ends[1] = abcd[1];
            return;
        }
        ends[0] = edge_ends[2 * std::size_t(e)], ends[1] = edge_ends[2 * std::size_t(e) + 1];
    }
};

// Whether a level's tables hold what their form says: the arrays' sizes, every index inside the level, the fans'
// layout and the interior edges' parent faces. Walks the tables: Debug builds (the sanitizer run) assert it of every
// level a plan keeps.
bool follows_table_layout(const LevelStencils& s);

// The tables of a level that is not built (form "interior", in the vertex plan and in face-varying layers), from its
// parent's connectivity, as refine_topology would have written them (its edges, wings and rings) but in one pass and
// with its edges inside the parent's faces left to `interior`, whose faces the caller hands over from the parent; and
// the faces of the last level after it (48 indices per parent face). The parent must hold its edge faces and vertex
// edges. `s.num_vertices` is set; `threads` share the work.
void fill_tables_from_parent(const Topology& parent, LevelStencils& s, std::int32_t* last_faces, int threads);

// The index tables of one kernel run, as plain pointers: a stored level's own (bases 0), or a derived level's for a
// chunk, filled just before the run. Vertex i's ring is ring[ring_offsets[i - vertex_base] ..
// ring_offsets[i - vertex_base + 1]); edge e's ends are edge_ends[2 (e - edge_base)] and the next, its wings
// edge_wing_c[e - edge_base] and edge_wing_d[e - edge_base].
struct StencilView {
    const std::int32_t *ring_offsets, *ring, *edge_ends, *edge_wing_c, *edge_wing_d;
    int vertex_base = 0, edge_base = 0;

    // Vertex i's ring: ring[ring_first(i) .. ring_first(i) + valence(i)).
    int ring_first(int i) const { return ring_offsets[i - vertex_base]; }
    int valence(int i) const { return ring_offsets[i - vertex_base + 1] - ring_offsets[i - vertex_base]; }
    // Edge e's ends A (0) and B (1), and its wings C and D.
    std::int32_t end(int e, int which) const { return edge_ends[2 * (e - edge_base) + which]; }
    std::int32_t wing_c(int e) const { return edge_wing_c[e - edge_base]; }
    std::int32_t wing_d(int e) const { return edge_wing_d[e - edge_base]; }
};

inline StencilView stored_view(const LevelStencils& s) {
    return {s.ring_offsets.data(), s.ring.data(), s.edge_ends.data(), s.edge_wing_c.data(), s.edge_wing_d.data(), 0, 0};
}

// Fills the smooth pass's weights for valences 0 .. max_valence from `mask(n)` (the refinement's or the limit's
// mask, anything with `self` and `ring`).
template <typename SmoothMask>
void set_smooth_masks(LevelStencils& s, int max_valence, SmoothMask mask) {
    s.smooth_self.resize(std::size_t(max_valence) + 1);
    s.smooth_ring.resize(std::size_t(max_valence) + 1);
    for (int n = 0; n <= max_valence; ++n) {
        const auto m = mask(n);
        s.smooth_self[n] = float(m.self);
        s.smooth_ring[n] = float(m.ring);
    }
}

// The smooth edge mask, as the kernels' smooth pass applies it to every edge.
inline constexpr float kSmoothEdgeEndWeight = float(smooth_edge_mask().a);
inline constexpr float kSmoothEdgeWingWeight = float(smooth_edge_mask().wings);

}  // namespace loopsub::detail
