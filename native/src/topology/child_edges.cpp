// A child level's edges read through the split's numbering (topology.h) instead of from a stored level: their ends
// and the vertices opposite them (child_edges, in edge order; child_edge_ends, one edge), and the halves' ends and
// wings as the split writes them (write_half_ends; write_half_wings, in face order, from each corner's place byte).
// The interior edges of a face are stored three at a time with SSE2 where the compiler targets it; the scalar loop
// takes the faces at the ends of a range.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "topology/level_relations.h"
#include "topology/topology.h"

namespace loopsub::detail {

namespace {

// The vertices opposite the two halves of parent edge e in their first two faces: (C, D) of half 2e, then of half
// 2e + 1; where a face is missing, C / D repeat the half's ends.
inline void half_edge_wings(const Topology& p, Index e, Index wings[4]) {
    const Index nv = p.num_vertices, a = p.edge_vertices[2 * e], b = p.edge_vertices[2 * e + 1], m = nv + e;
    Index at_a[2] = {a, m}, at_b[2] = {m, b};
    int face = 0;
    for (Index k = p.edge_face_offsets[e]; k < p.edge_face_offsets[e + 1] && face < 2; ++k, ++face) {
        const Index f = p.edge_faces[k];
        const Index* fe = &p.face_edges[3 * f];
        const int local = local_edge(fe, e);
        face_wings(nv, fe, local, p.face_vertices[3 * f + local] == a, at_a[face], at_b[face]);
    }
    wings[0] = at_a[0], wings[1] = at_a[1], wings[2] = at_b[0], wings[3] = at_b[1];
}

// Ends and wings of interior edge k of face f (face_interior_edge).
inline void interior_edge(const Topology& p, Index f, int k, Index abcd[4]) {
    face_interior_edge(p.num_vertices, &p.face_vertices[3 * f], &p.face_edges[3 * f], k, abcd);
}

}  // namespace

void child_edges(const Topology& p, int begin, int end, Index* ends, Index* c, Index* d) {
    const Index nv = p.num_vertices, halves = 2 * p.num_edges();
    auto put = [&](int e, Index a, Index b, Index wing_c, Index wing_d) {
        const int k = e - begin;
        ends[2 * k] = a, ends[2 * k + 1] = b, c[k] = wing_c, d[k] = wing_d;
    };
    // Halves 2h and 2h + 1 of parent edge h share their wings' search.
    for (int h = begin / 2; h < (std::min(end, halves) + 1) / 2; ++h) {
        Index wings[4];
        half_edge_wings(p, h, wings);
        if (2 * h >= begin) put(2 * h, p.edge_vertices[2 * h], nv + h, wings[0], wings[1]);
        if (2 * h + 1 < end) put(2 * h + 1, nv + h, p.edge_vertices[2 * h + 1], wings[2], wings[3]);
    }
    // Interior edges, three per face.
    const int interior_begin = std::max(begin, halves) - halves, interior_end = end - halves;
    for (int f = interior_begin / 3; f < (interior_end + 2) / 3; ++f) {
#if defined(__SSE2__)
        // A face whose edges are all in range, the next face's first too, in four stores rather than twelve: the
        // vector loads read that face's first corner, and the 16-byte stores of C and D spill into its slot.
        if (3 * f >= interior_begin && 3 * f + 3 < interior_end) {
            const __m128i m = _mm_add_epi32(load_corners(&p.face_edges[3 * std::size_t(f)]), _mm_set1_epi32(nv));
            const __m128i v = load_corners(&p.face_vertices[3 * std::size_t(f)]);
            const int k = halves + 3 * f - begin;
            _mm_storeu_si128(reinterpret_cast<__m128i*>(ends + 2 * k),
                             _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 1, 1, 0)));  // m0 m1 m1 m2
            _mm_storel_epi64(reinterpret_cast<__m128i*>(ends + 2 * k + 4),
                             _mm_shuffle_epi32(m, _MM_SHUFFLE(0, 0, 0, 2)));  // m2 m0
            _mm_storeu_si128(reinterpret_cast<__m128i*>(c + k),
                             _mm_shuffle_epi32(v, _MM_SHUFFLE(3, 0, 2, 1)));  // v1 v2 v0
            _mm_storeu_si128(reinterpret_cast<__m128i*>(d + k),
                             _mm_shuffle_epi32(m, _MM_SHUFFLE(3, 1, 0, 2)));  // m2 m0 m1
            continue;
        }
#endif
        for (int k = 0; k < 3; ++k) {
            const int e = halves + 3 * f + k;
            if (e < begin || e >= end) continue;
            Index abcd[4];
            interior_edge(p, f, k, abcd);
            put(e, abcd[0], abcd[1], abcd[2], abcd[3]);
        }
    }
}

void write_half_ends(const Topology& p, int e0, int e1, Index* ends) {
    const Index nv = p.num_vertices;
    for (int e = e0; e < e1; ++e, ends += 4) {  // half 2e = (a, m), 2e + 1 = (m, b)
        ends[0] = p.edge_vertices[2 * e], ends[1] = ends[2] = nv + e, ends[3] = p.edge_vertices[2 * e + 1];
    }
}

void write_half_wings(const Topology& p, int f0, int f1, int e0, int e1, Index* c, Index* d) {
    const Index nv = p.num_vertices;
    // Every edge has a face; where it has no second, its halves' D wings are their own ends (as half_edge_wings).
    for (int e = e0; e < e1; ++e) {
        if (p.edge_face_count(e) >= 2) continue;
        d[2 * e] = nv + e;
        d[2 * e + 1] = p.edge_vertices[2 * e + 1];
    }
    for (int f = f0; f < f1; ++f) {
        const Index* fe = &p.face_edges[3 * f];
        const std::uint8_t* places = &p.face_edge_places[3 * std::size_t(f)];
        for (int k = 0; k < 3; ++k) {
            const int place = places[k] >> 1;
            if (place > 1) continue;
            Index* wing = place == 0 ? c : d;
            face_wings(nv, fe, k, places[k] & 1, wing[2 * fe[k]], wing[2 * fe[k] + 1]);
        }
    }
}

void child_edge_ends(const Topology& p, Index e, Index ends[2]) { child_edge_ends_of(StoredLevel{p}, e, ends); }

}  // namespace loopsub::detail
