// Where a base level is no surface: its non-manifold edges (more than two faces, or two that run along the edge the
// same way) and vertices (on such an edge, or with faces that form no single fan), which the plan builder treats as
// OpenSubdiv does; and faces_between, the count of faces walking around a manifold vertex from one edge to another,
// which the rules' crease classes ask for.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/parallel.h"
#include "topology/topology.h"

namespace loopsub::detail {

std::vector<std::uint8_t> non_manifold_edges(const Topology& t) {
    // Consistently wound neighbours run along a shared edge in opposite directions. An edge's first face runs along it
    // from its first end (the edge took its ends from that corner), so an edge of two faces winds inconsistently where
    // its second face does so too: a place byte of 0b11 (second face, starts the edge). One pass over the place bytes,
    // rather than counting directions per corner, which reads each corner's edge ends (docs/benchmark.md, "Measurements
    // behind the code").
    std::vector<std::uint8_t> flags(t.num_edges(), 0);
    // Plain pointers: a byte store may alias anything, so the vectors' data pointers would be read again each time.
    std::uint8_t* flag = flags.data();
    const Index* face_offsets = t.edge_face_offsets.data();
    for (int e = 0; e < t.num_edges(); ++e) flag[e] = face_offsets[e + 1] - face_offsets[e] > 2;
    const std::uint8_t* places = t.face_edge_places.data();
    const Index* corner_edges = t.face_edges.data();
    for (std::size_t c = 0; c < t.face_edge_places.size(); ++c)
        if (places[c] == (1 << 1 | 1)) flag[corner_edges[c]] = 1;
    return flags;
}

std::vector<std::uint8_t> non_manifold_vertices(const Topology& t, const std::vector<std::uint8_t>& non_manifold_edge,
                                                int threads) {
    std::vector<std::uint8_t> flags(t.num_vertices, 0);
    auto flag_part = [&](int, int part, int parts) {
        const auto [v0, v1] = part_of(t.num_vertices, part, parts);
        for (int v = v0; v < v1; ++v) {
            const Index first = t.vertex_edge_offsets[v], last = t.vertex_edge_offsets[v + 1];
            if (first == last) continue;
            int face_corners = 0;  // each face at v has two edges at v
            Index boundary_edge = -1;
            bool bad = false;
            for (Index k = first; k < last; ++k) {
                const Index e = t.vertex_edges[k];
                bad |= non_manifold_edge[e] != 0;
                face_corners += t.edge_face_count(e);
                if (t.edge_face_count(e) == 1) boundary_edge = e;
            }
            if (bad) {
                flags[v] = 1;
                continue;
            }
            const int num_faces = face_corners / 2;
            // Walk the fan from a boundary edge (or any edge) and count the faces reached.
            Index e = boundary_edge >= 0 ? boundary_edge : t.vertex_edges[first];
            const Index start = e;
            Index f = t.edge_faces[t.edge_face_offsets[e]];
            int reached = 0;
            while (true) {
                ++reached;
                e = t.other_edge_at_vertex(f, v, e);
                if (e == start || t.edge_face_count(e) != 2 || reached > num_faces) break;
                const Index* faces = &t.edge_faces[t.edge_face_offsets[e]];
                f = faces[0] == f ? faces[1] : faces[0];
            }
            flags[v] = reached != num_faces;
        }
    };
    run_levels(std::max(1, threads), 1, flag_part, kPiecesPerThread);  // taken in turn: a second thread starts late
    return flags;
}

int faces_between(const Topology& t, Index v, Index from, Index to) {
    Index e = from;
    Index f = t.edge_faces[t.edge_face_offsets[e]];
    int count = 0;
    while (true) {
        ++count;
        e = t.other_edge_at_vertex(f, v, e);
        if (e == to || e == from || t.edge_face_count(e) != 2) return count;
        const Index* faces = &t.edge_faces[t.edge_face_offsets[e]];
        f = faces[0] == f ? faces[1] : faces[0];
    }
}

}  // namespace loopsub::detail
