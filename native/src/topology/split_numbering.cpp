// The invariant every derivation from a parent relies on: that a child holds the split's numbering (topology.h,
// above Refined) in every array it has, exactly as the derivations from the parent give it (follows_split_numbering).
// A walk over the whole level, for Debug builds (the sanitizer run), where refine_topology asserts it after each
// split, and for the tests.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

bool follows_split_numbering(const Topology& p, const Topology& c) {
    const Index nv = p.num_vertices, ne = p.num_edges(), nf = p.num_faces();
    if (c.num_vertices != nv + ne || c.num_faces() != 4 * nf) return false;
    for (Index f = 0; f < nf; ++f) {
        const Index* v = &p.face_vertices[3 * f];
        const Index* fe = &p.face_edges[3 * f];
        const Index* children = &c.face_vertices[12 * std::size_t(f)];
        for (int k = 0; k < 3; ++k) {
            const Index corner_child[3] = {v[k], nv + fe[k], nv + fe[prev_corner(k)]};
            if (!std::equal(corner_child, corner_child + 3, children + 3 * k) || children[9 + k] != nv + fe[k])
                return false;
        }
    }
    if (c.edge_vertices.empty()) return true;  // FacesOnly
    const int child_edges = 2 * ne + 3 * nf;
    if (c.num_edges() != child_edges) return false;
    for (Index e = 0; e < child_edges; ++e) {
        Index ends[2];
        child_edge_ends(p, e, ends);
        if (ends[0] != c.edge_vertices[2 * e] || ends[1] != c.edge_vertices[2 * e + 1]) return false;
    }
    // Edge i of a face joins its corners i and i + 1; the places say which end the face starts it at.
    for (std::size_t corner = 0; corner < c.face_vertices.size(); ++corner) {
        const Index e = c.face_edges[corner], from = c.face_vertices[corner];
        const Index to = c.face_vertices[corner - corner % 3 + std::size_t(next_corner(int(corner % 3)))];
        const Index a = c.edge_vertices[2 * e], b = c.edge_vertices[2 * e + 1];
        if (!((a == from && b == to) || (a == to && b == from))) return false;
        if (!c.face_edge_places.empty() && (c.face_edge_places[corner] & 1) != (a == from ? 1 : 0)) return false;
    }
    for (Index v = 0; v <= c.num_vertices; ++v)
        if (c.vertex_edge_offsets[v] != child_ring_offset(p, v)) return false;
    if (!c.edge_wing_c.empty()) {
        std::vector<Index> ends(2 * std::size_t(child_edges)), wing_c(child_edges), wing_d(child_edges),
            ring(c.vertex_vertices.size());
        detail::child_edges(p, 0, child_edges, ends.data(), wing_c.data(), wing_d.data());
        write_child_rings(p, 0, c.num_vertices, ring.data());
        if (!std::equal(wing_c.begin(), wing_c.end(), c.edge_wing_c.begin()) ||
            !std::equal(wing_d.begin(), wing_d.end(), c.edge_wing_d.begin()) ||
            !std::equal(ring.begin(), ring.end(), c.vertex_vertices.begin()))
            return false;
    }
    if (!c.vertex_edges.empty()) {
        for (Index v = 0; v < c.num_vertices; ++v)
            for (Index k = c.vertex_edge_offsets[v]; k < c.vertex_edge_offsets[v + 1]; ++k) {
                const Index e = c.vertex_edges[k];
                if (c.edge_vertices[2 * e] != v && c.edge_vertices[2 * e + 1] != v) return false;
            }
        for (Index e = 0; e < child_edges; ++e)
            for (Index k = c.edge_face_offsets[e]; k < c.edge_face_offsets[e + 1]; ++k) {
                const Index* face_edges = &c.face_edges[3 * std::size_t(c.edge_faces[k])];
                if (std::find(face_edges, face_edges + 3, e) == face_edges + 3) return false;
            }
    }
    return true;
}

}  // namespace loopsub::detail
