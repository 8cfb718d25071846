// The stencil tables of a level that is not built, from its parent's connectivity (see stencils.h).
#include <cstring>
#include <memory>
#include <utility>

#include "parallel.h"
#include "stencils.h"

namespace loopsub::detail {

void fill_tables_from_parent(const Topology& parent, LevelStencils& s, Index* last_faces, int threads) {
    // What refine_topology would have written (Refined::ForStencils), without the level's faces and in one pass; the
    // edges inside the parent's faces are read from those faces (LevelStencils::interior: the caller hands them over).
    const int nv = parent.num_vertices, halves = 2 * parent.num_edges();
    s.ring_offsets.resize(std::size_t(s.num_vertices) + 1);
    s.ring.resize(std::size_t(child_ring_offset(parent, s.num_vertices)));
    s.edge_ends.resize(2 * std::size_t(halves));
    s.edge_c.resize(std::size_t(halves));
    s.edge_d.resize(std::size_t(halves));
    s.interior = std::make_unique<LevelStencils::InteriorFaces>();
    s.interior->first_edge = halves;
    s.interior->parent_vertices = nv;
    // Each part takes its share of each kind of vertex, edge and face. Two steps: the halves' wings are scattered by
    // face, and a midpoint's ring is read back from its edge's wings (midpoint_ring_face in topology.cpp: the ring is
    // the edge's ends, then its halves' wings face by face), a stream rather than a search of each face (0.42 ms).
    // The last level's faces are written in the first step too (write_grandchild_faces), the step's pieces taking
    // tables and faces in turn: the faces' stores (16 MB for 1.3M triangles) wait on memory, the tables' passes on
    // the cores. Side by side rather than one pass after the other, two-thread plans of the benchmark meshes were 4-7 %
    // faster, plans with an evaluation 4-7 % too (paired medians of 300, interleaved in one process; one thread alike).
    constexpr int pieces_per_thread = 4;
    run_levels(std::max(1, threads), 2, [&](int step, int piece, int pieces) {
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
            // The halves (two per parent edge): ends in edge order, wings in face order (write_half_wings, twice as
            // fast as in edge order).
            const auto [f0, f1] = share(0, parent.num_faces());
            write_half_ends(parent, e0, e1, s.edge_ends.data() + 4 * std::size_t(e0));
            write_half_wings(parent, f0, f1, e0, e1, s.edge_c.data(), s.edge_d.data());
            return;
        }
        // Plain pointers: the pairs' copies may alias anything, so the vectors' data pointers would be read again each time.
        const Index *ends = parent.edge_vertices.data(), *face_offsets = parent.edge_face_offsets.data();
        const Index *wing_c = s.edge_c.data(), *wing_d = s.edge_d.data();
        Index *ring_offsets = s.ring_offsets.data(), *rings = s.ring.data();
        const Index old_entries = parent.vertex_edge_offsets[nv];
        for (int e = e0; e < e1; ++e) {
            const Index first = old_entries + 2 * e + 2 * face_offsets[e], faces = face_offsets[e + 1] - face_offsets[e];  // child_ring_offset
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
    }, pieces_per_thread);
}

}  // namespace loopsub::detail
