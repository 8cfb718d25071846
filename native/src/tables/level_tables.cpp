// A level's tables (stencils.h): those of a level that is not built, filled from its parent's connectivity, and the
// check that any level's tables hold what their form says.
#include <algorithm>
#include <cstring>
#include <memory>
#include <utility>

#include "base/parallel.h"
#include "tables/stencils.h"

namespace loopsub::detail {

void fill_tables_from_parent(const Topology& parent, LevelStencils& s, Index* last_faces, int threads) {
    // What refine_topology would have written (Refined::Full, less the edge faces and vertex edges), without the
    // level's faces and in one pass; the edges inside the parent's faces are read from those faces
    // (LevelStencils::interior: the caller hands them over).
    const int nv = parent.num_vertices, halves = 2 * parent.num_edges();
    s.ring_offsets.resize(std::size_t(s.num_vertices) + 1);
    s.ring.resize(std::size_t(child_ring_offset(parent, s.num_vertices)));
    s.edge_ends.resize(2 * std::size_t(halves));
    s.edge_wing_c.resize(std::size_t(halves));
    s.edge_wing_d.resize(std::size_t(halves));
    s.interior = std::make_unique<LevelStencils::InteriorFaces>();
    s.interior->first_edge = halves;
    s.interior->parent_vertices = nv;
    // Each part takes its share of each kind of vertex, edge and face. Two steps: the halves' wings are scattered by
    // face, and a midpoint's ring is read back from its edge's wings (midpoint_ring_face in topology/: the ring is
    // the edge's ends, then its halves' wings face by face), a stream rather than a search of each face. The last
    // level's faces are written in the first step too (write_grandchild_faces), the step's pieces taking tables and
    // faces in turn: the faces' stores (16 MB for 1.3M triangles) wait on memory, the tables' passes on the cores, so
    // side by side they take less than one after the other (docs/benchmark.md, "Measurements behind the code").
    constexpr int pieces_per_thread = 8;
    run_levels(
        std::max(1, threads), 2,
        [&](int step, int piece, int pieces) {
            int part = piece, parts = pieces;
            if (step == 0 && pieces == 1) {
                write_grandchild_faces(parent, 0, parent.num_faces(), last_faces);
            } else if (step == 0) {  // even pieces: tables, odd pieces: faces
                part = piece / 2, parts = pieces / 2;
                if (piece % 2) {
                    const auto [f0, f1] = part_of(parent.num_faces(), part, parts);
                    write_grandchild_faces(parent, f0, f1, last_faces);
                    return;
                }
            }
            // This part's share of [begin, end).
            auto share = [part, parts](int begin, int end) {
                const auto [first, last] = part_of(end - begin, part, parts);
                return std::pair<int, int>(begin + first, begin + last);
            };
            const auto [e0, e1] = share(0, parent.num_edges());
            if (step == 0) {
                const auto [v0, v1] = share(0, nv);
                for (int v = v0; v < v1; ++v) s.ring_offsets[v] = parent.vertex_edge_offsets[v];
                // Pointer arithmetic, not &vector[i]: the offset may be the ring's end.
                write_child_rings(parent, v0, v1, s.ring.data() + parent.vertex_edge_offsets[v0]);
                // The halves (two per parent edge): ends in edge order, wings in face order (write_half_wings).
                const auto [f0, f1] = share(0, parent.num_faces());
                write_half_ends(parent, e0, e1, s.edge_ends.data() + 4 * std::size_t(e0));
                write_half_wings(parent, f0, f1, e0, e1, s.edge_wing_c.data(), s.edge_wing_d.data());
                return;
            }
            // Plain pointers: the pairs' copies may alias anything, so the vectors' data pointers would be read again
            // each time.
            const Index *ends = parent.edge_vertices.data(), *face_offsets = parent.edge_face_offsets.data();
            const Index *wing_c = s.edge_wing_c.data(), *wing_d = s.edge_wing_d.data();
            Index *ring_offsets = s.ring_offsets.data(), *rings = s.ring.data();
            const Index old_entries = parent.vertex_edge_offsets[nv];
            for (int e = e0; e < e1; ++e) {
                const Index first = old_entries + 2 * e + 2 * face_offsets[e],
                            faces = face_offsets[e + 1] - face_offsets[e];  // child_ring_offset
                ring_offsets[nv + e] = first;
                Index* ring = rings + first;
                std::memcpy(ring, ends + 2 * std::size_t(e), 2 * sizeof(Index));
                if (faces > 2) {  // the wing tables keep two faces; the ring has them all
                    write_child_rings(parent, nv + e, nv + e + 1, ring);
                    continue;
                }
                if (faces > 0) std::memcpy(ring + 2, wing_c + 2 * std::size_t(e), 2 * sizeof(Index));
                if (faces > 1) std::memcpy(ring + 4, wing_d + 2 * std::size_t(e), 2 * sizeof(Index));
            }
            if (part + 1 == parts) s.ring_offsets[s.num_vertices] = Index(s.ring.size());
        },
        pieces_per_thread);
}

bool follows_table_layout(const LevelStencils& s) {
    if (s.derived_from) {
        const Topology& p = *s.derived_from;
        return s.num_vertices == p.num_vertices + p.num_edges() &&
               s.num_edges == 2 * p.num_edges() + 3 * p.num_faces() && s.ring.empty() && s.edge_ends.empty() &&
               !s.interior && s.fan_midpoints == 0;
    }
    const std::size_t stored_edges = std::size_t(s.interior ? s.interior->first_edge : s.num_edges);
    if (s.ring_offsets.size() != std::size_t(s.num_vertices) + 1 ||
        s.ring.size() != std::size_t(s.ring_offsets.back()) || s.edge_ends.size() != 2 * stored_edges ||
        s.edge_wing_c.size() != stored_edges || s.edge_wing_d.size() != stored_edges)
        return false;
    auto inside = [&s](std::int32_t v) { return v >= 0 && v < s.num_vertices; };
    if (!std::all_of(s.ring.begin(), s.ring.end(), inside) ||
        !std::all_of(s.edge_ends.begin(), s.edge_ends.end(), inside) ||
        !std::all_of(s.edge_wing_c.begin(), s.edge_wing_c.end(), inside) ||
        !std::all_of(s.edge_wing_d.begin(), s.edge_wing_d.end(), inside))
        return false;
    // Fans: midpoint m of parent edge h has the halves 2h = (a, m) and 2h + 1 = (m, b); a midpoint of two faces
    // (valence 6) has the ring (a, b, c[2h], c[2h + 1], d[2h], d[2h + 1]), the seven points the fan kernels read.
    if (s.fan_midpoints > 0) {
        if (s.fan_first_midpoint + s.fan_midpoints != s.num_vertices || 2 * std::size_t(s.fan_midpoints) > stored_edges)
            return false;
        const StencilView t = stored_view(s);
        for (int h = 0; h < s.fan_midpoints; ++h) {
            const int m = s.fan_first_midpoint + h;
            if (t.end(2 * h, 1) != m || t.end(2 * h + 1, 0) != m) return false;
            const std::int32_t fan[6] = {t.end(2 * h, 0),     t.end(2 * h + 1, 1), t.wing_c(2 * h),
                                         t.wing_c(2 * h + 1), t.wing_d(2 * h),     t.wing_d(2 * h + 1)};
            if (t.valence(m) == 6 && !std::equal(fan, fan + 6, t.ring + t.ring_first(m))) return false;
        }
    }
    // Interior edges: three per parent face, after the halves of the parent's edges.
    if (s.interior) {
        const LevelStencils::InteriorFaces& interior = *s.interior;
        const std::size_t interior_edges = std::size_t(s.num_edges - interior.first_edge);
        return interior.first_edge == 2 * s.fan_midpoints && interior.parent_vertices == s.fan_first_midpoint &&
               interior.face_vertices.size() == interior_edges && interior.face_edges.size() == interior_edges;
    }
    return true;
}

}  // namespace loopsub::detail
