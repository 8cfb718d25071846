// The topology layer's own helpers, shared by its files and included by no other layer (topology.h is the layer's
// public header): where an edge sits in a face, what a split gives the midpoint of an edge (its wings, ring and edges
// inside a face), a stored level read through the calls the derivations make of any parent level (StoredLevel), the
// child's faces, edge ends and maxima derived from such a parent through the split's numbering (topology.h), and the
// SSE2 helpers of the writers that store 16 bytes at a time (split.cpp, child_edges.cpp, grandchild_faces.cpp).
// Internal linkage, as in kernels_quads.h: inline in each file of the layer, and no name here meets one of another
// layer.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstring>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {
namespace {

// Where edge e sits in face f's edges (edge k runs from corner k to corner k + 1).
inline int local_edge(const Index* face_edges, Index e) { return face_edges[0] == e ? 0 : face_edges[1] == e ? 1 : 2; }

// The vertices opposite the two halves of a face's edge `local` (fe: the face's edges) in that face: at_a opposite
// the half at the edge's first vertex, at_b opposite the other. A half lies in a corner child (v_k, m_k, m_{k-1}),
// opposite the other midpoint there; a_first: the face's corner `local` is the edge's first vertex.
inline void face_wings(Index nv, const Index* fe, int local, bool a_first, Index& at_a, Index& at_b) {
    const Index before = nv + fe[prev_corner(local)], after = nv + fe[next_corner(local)];
    at_a = a_first ? before : after;
    at_b = a_first ? after : before;
}

// The ring of the midpoint of edge e: its ends, then per face of e the two midpoints it is joined to there, which are
// the wings of e's halves in that face (face_wings: at a, then at b). The plan reads the level before the last's rings
// back from its wing tables (fill_tables_from_parent). Each returns the ring's next free entry.
inline Index* midpoint_ring_ends(const Topology& p, Index e, Index* ring) {
    ring[0] = p.edge_vertices[2 * e], ring[1] = p.edge_vertices[2 * e + 1];
    return ring + 2;
}
inline Index* midpoint_ring_face(Index nv, const Index* fe, int local, bool a_first, Index* ring) {
    face_wings(nv, fe, local, a_first, ring[0], ring[1]);
    return ring + 2;
}

// The midpoint's edges inside a face of its edge (the edge is the face's edge `local`), in its ring's order: interior
// edge local joins midpoints local and local + 1, edge local - 1 joins local - 1 and local, and the one to the
// midpoint next to the edge's first vertex comes first.
inline void midpoint_face_edges(Index interior_base, Index f, int local, bool a_first, Index edges[2]) {
    edges[0] = interior_base + 3 * f + (a_first ? prev_corner(local) : local);
    edges[1] = interior_base + 3 * f + (a_first ? local : prev_corner(local));
}

// A stored level read through the calls the derivations (below, and vertex_neighbourhood.cpp's) make of a parent,
// which a VertexNeighbourhood answers for a level known through its own parent. fan: vertex_neighbourhood.cpp.
struct StoredLevel {
    const Topology& t;
    int num_vertices() const { return t.num_vertices; }
    int num_edges() const { return t.num_edges(); }
    int num_faces() const { return t.num_faces(); }
    int max_valence() const { return t.max_valence; }
    int max_edge_face_count() const { return t.max_edge_face_count; }
    void edge_ends(Index e, Index ends[2]) const {
        ends[0] = t.edge_vertices[2 * std::size_t(e)], ends[1] = t.edge_vertices[2 * std::size_t(e) + 1];
    }
    void face_vertices(Index f, Index out[3]) const { std::copy_n(&t.face_vertices[3 * std::size_t(f)], 3, out); }
    void face_edges(Index f, Index out[3]) const { std::copy_n(&t.face_edges[3 * std::size_t(f)], 3, out); }
    void face(Index f, Index vertices[3], Index edges[3]) const { face_vertices(f, vertices), face_edges(f, edges); }
    int edge_face_count(Index e) const { return t.edge_face_count(e); }
    template <typename Visit>
    void for_each_edge_face(Index e, const Visit& visit) const {
        for (Index k = t.edge_face_offsets[e]; k < t.edge_face_offsets[e + 1]; ++k) visit(t.edge_faces[k]);
    }
    void edges(Index v, std::vector<Index>& out) const {
        out.assign(t.vertex_edges.begin() + t.vertex_edge_offsets[v],
                   t.vertex_edges.begin() + t.vertex_edge_offsets[v + 1]);
    }
    int faces_between(Index v, Index from, Index to) const { return detail::faces_between(t, v, from, to); }
    void fan(Index v, std::vector<FanCorner>& out) const;
};

// The child's connectivity around single elements, from any parent level P (StoredLevel or VertexNeighbourhood) through
// the split's numbering (topology.h), as refine_topology writes it.

template <typename P>
Index child_edge_at_of(const P& p, Index e, Index v) {
    Index ends[2];
    p.edge_ends(e, ends);
    assert(ends[0] == v || ends[1] == v);
    return 2 * e + (ends[0] == v ? 0 : 1);
}

// The corners of child face c (4f + j of parent face f: the corner child (v_j, m_j, m_j-1), or the middle child (m_0,
// m_1, m_2)) and, where asked, its edges (the corner child's half of edge j, the interior edge across, its half of
// edge j - 1; the middle child's three interior edges).
template <typename P>
void child_face_of(const P& p, Index c, Index vertices[3], Index* edges) {
    const Index f = c / 4, nv = p.num_vertices(), interior = 2 * p.num_edges() + 3 * f;
    const int j = int(c % 4);
    Index v[3], e[3];
    p.face(f, v, e);
    if (j == 3) {
        for (int k = 0; k < 3; ++k) vertices[k] = nv + e[k];
        if (edges) edges[0] = interior, edges[1] = interior + 1, edges[2] = interior + 2;
        return;
    }
    vertices[0] = v[j], vertices[1] = nv + e[j], vertices[2] = nv + e[prev_corner(j)];
    if (!edges) return;
    edges[0] = child_edge_at_of(p, e[j], v[j]);
    edges[1] = interior + prev_corner(j);
    edges[2] = child_edge_at_of(p, e[prev_corner(j)], v[j]);
}

// child_edge_ends (child_edges.cpp) from any parent.
template <typename P>
void child_edge_ends_of(const P& p, Index e, Index ends[2]) {
    const Index nv = p.num_vertices(), halves = 2 * p.num_edges();
    if (e < halves) {  // half 2h = (a, m), 2h + 1 = (m, b)
        Index parent_ends[2];
        p.edge_ends(e / 2, parent_ends);
        ends[0] = e % 2 == 0 ? parent_ends[0] : nv + e / 2;
        ends[1] = e % 2 == 0 ? nv + e / 2 : parent_ends[1];
        return;
    }
    const Index f = (e - halves) / 3;
    const int k = (e - halves) % 3;
    Index fe[3];
    p.face_edges(f, fe);
    ends[0] = nv + fe[k];
    ends[1] = nv + fe[next_corner(k)];
}

template <typename P>
int child_max_valence_of(const P& p) {
    return p.num_edges() > 0 ? std::max(p.max_valence(), 2 + 2 * p.max_edge_face_count()) : p.max_valence();
}
template <typename P>
int child_max_edge_face_count_of(const P& p) {
    return p.num_faces() > 0 ? std::max(p.max_edge_face_count(), 2) : p.max_edge_face_count();
}

#if defined(__SSE2__)
// The layer's SSE2 writers (the loops that write a level's tables are bound by their count of stores, one a cycle here,
// so they store 16 bytes at a time): lane k of a vector belongs to corner k of a face, lane 3 is unused.
inline __m128i load_corners(const Index* face) { return _mm_loadu_si128(reinterpret_cast<const __m128i*>(face)); }
inline __m128i corner_before(__m128i x) { return _mm_shuffle_epi32(x, _MM_SHUFFLE(3, 1, 0, 2)); }  // lane k: x[k - 1]

// Row k = (a_k, b_k, c_k, d_k), for k < 3.
inline void corner_rows(__m128i a, __m128i b, __m128i c, __m128i d, __m128i row[3]) {
    const __m128i ab_lo = _mm_unpacklo_epi32(a, b), cd_lo = _mm_unpacklo_epi32(c, d);
    row[0] = _mm_unpacklo_epi64(ab_lo, cd_lo);
    row[1] = _mm_unpackhi_epi64(ab_lo, cd_lo);
    row[2] = _mm_unpacklo_epi64(_mm_unpackhi_epi32(a, b), _mm_unpackhi_epi32(c, d));
}

// corner_halves for the three corners of face f at once: the child edges of edge k and of edge k - 1 at v_k.
inline void corner_halves_sse2(const Topology& p, Index f, __m128i fe, __m128i& of_edge, __m128i& of_edge_before) {
    int places;
    std::memcpy(&places, &p.face_edge_places[3 * std::size_t(f)], sizeof places);
    const __m128i zero = _mm_setzero_si128();
    const __m128i starts =
        _mm_and_si128(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(places), zero), zero), _mm_set1_epi32(1));
    const __m128i twice = _mm_add_epi32(fe, fe);
    of_edge = _mm_sub_epi32(_mm_add_epi32(twice, _mm_set1_epi32(1)), starts);
    of_edge_before = corner_before(_mm_add_epi32(twice, starts));
}
#endif

}  // namespace
}  // namespace loopsub::detail
