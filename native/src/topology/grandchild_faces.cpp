// The faces of the grandchild level, two splits on, written straight from the parent's faces through the split's
// numbering (topology.h), without the child (write_grandchild_faces): what a plan without the limit surface outputs,
// never building the level before the last. A scalar loop, for a parent with or without face_edge_places, and beside
// it its SSE2 twin, which a parent with places takes for all faces but the last (its loads read into the next face);
// both write the same indices.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "topology/level_relations.h"
#include "topology/topology.h"
#include "topology/triangle_corners.h"

namespace loopsub::detail {

namespace {

// write_grandchild_faces for a parent with face_edge_places (Places: which end each face edge starts at, with no
// read of the edge's ends) or without (Refined::Connectivity).
template <bool Places>
void grandchild_faces(const Topology& p, int f0, int f1, Index* out) {
    const Index nv = p.num_vertices, interior_base = 2 * p.num_edges();
    const Index child_vertices = nv + p.num_edges();  // the grandchild's midpoint of child edge E is child_vertices + E
    out += 48 * std::size_t(f0);
    for (int f = f0; f < f1; ++f) {
        const Index* v = &p.face_vertices[3 * f];
        const Index* fe = &p.face_edges[3 * f];
        const Index m[3] = {nv + fe[0], nv + fe[1], nv + fe[2]};
        const Index interior = interior_base + 3 * f;
        // The four children as refine_topology numbers them, each with its corners and edges (edge i from corner i
        // to corner i + 1), then each child split the same way.
        Index corners[4][3], edges[4][3];
        for (int k = 0; k < 3; ++k) {
            const int before = prev_corner(k);
            corners[k][0] = v[k], corners[k][1] = m[k], corners[k][2] = m[before];
            // The halves at v_k of edge k (which v_k starts) and of edge k - 1 (which v_k ends).
            if constexpr (Places) {
                const std::uint8_t* places = &p.face_edge_places[3 * std::size_t(f)];
                edges[k][0] = 2 * fe[k] + 1 - (places[k] & 1);
                edges[k][2] = 2 * fe[before] + (places[before] & 1);
            } else {
                edges[k][0] = child_edge_at(p, fe[k], v[k]);
                edges[k][2] = child_edge_at(p, fe[before], v[k]);
            }
            edges[k][1] = interior + before;
            corners[3][k] = m[k];
            edges[3][k] = interior + k;
        }
        for (int child = 0; child < 4; ++child, out += 12) {
            const Index a = corners[child][0], b = corners[child][1], c = corners[child][2];
            const Index m0 = child_vertices + edges[child][0], m1 = child_vertices + edges[child][1],
                        m2 = child_vertices + edges[child][2];
            out[0] = a, out[1] = m0, out[2] = m2, out[3] = b, out[4] = m1, out[5] = m0;
            out[6] = c, out[7] = m2, out[8] = m1, out[9] = m0, out[10] = m1, out[11] = m2;
        }
    }
}

#if defined(__SSE2__)
// grandchild_faces<true> with 16-byte stores: 12 per face rather than 48 one index at a time, which is what bounds
// the scalar loop (the last level's 1.3M triangles are 3.9M stores). Lane k of each vector below belongs to corner
// child k; a 4 x 4 transpose turns them into the children's rows. Reads four indices (and four places) from 3f, so
// the face after f must exist.
void grandchild_faces_sse2(const Topology& p, int f0, int f1, Index* out) {
    const Index nv = p.num_vertices, interior_base = 2 * p.num_edges();
    const __m128i child_vertices = _mm_set1_epi32(nv + p.num_edges());
    auto select = [](__m128i mask, __m128i if_set, __m128i otherwise) {
        return _mm_or_si128(_mm_and_si128(mask, if_set), _mm_andnot_si128(mask, otherwise));
    };
    const __m128i lanes_0_3 = _mm_setr_epi32(-1, 0, 0, -1), lane_2 = _mm_setr_epi32(0, 0, -1, 0);
    __m128i* o = reinterpret_cast<__m128i*>(out + 48 * std::size_t(f0));
    for (int f = f0; f < f1; ++f, o += 12) {
        const __m128i v = load_corners(&p.face_vertices[3 * std::size_t(f)]);
        const __m128i fe = load_corners(&p.face_edges[3 * std::size_t(f)]);
        const __m128i m = _mm_add_epi32(fe, _mm_set1_epi32(nv));
        // Grandchild midpoints of: the half of edge k at v_k, the half of edge k - 1 at v_k, interior edge k (and k -
        // 1).
        __m128i half_k, half_before;
        corner_halves_sse2(p, f, fe, half_k, half_before);
        half_k = _mm_add_epi32(half_k, child_vertices);
        half_before = _mm_add_epi32(half_before, child_vertices);
        const __m128i interior = _mm_add_epi32(_mm_add_epi32(child_vertices, _mm_set1_epi32(interior_base + 3 * f)),
                                               _mm_setr_epi32(0, 1, 2, 0));
        const __m128i interior_before = corner_before(interior);
        // Corner child k: (v_k, m_k, m_{k-1}), its edges' midpoints half_k, interior_before_k, half_before_k.
        __m128i first[3], second[3], third[3];
        corner_rows(v, half_k, half_before, m, first);
        corner_rows(interior_before, half_k, corner_before(m), half_before, second);
        corner_rows(interior_before, half_k, interior_before, half_before, third);
        for (int k = 0; k < 3; ++k) {
            _mm_storeu_si128(o + 3 * k, first[k]);
            _mm_storeu_si128(o + 3 * k + 1, second[k]);
            _mm_storeu_si128(o + 3 * k + 2, third[k]);
        }
        // The middle child (m_0, m_1, m_2), its edges' midpoints the interior ones: (m0 i0 i2 m1) (i1 i0 m2 i2) (i1 i0
        // i1 i2).
        const __m128i i0 = _mm_shuffle_epi32(interior, _MM_SHUFFLE(0, 2, 0, 0));
        _mm_storeu_si128(o + 9, select(lanes_0_3, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 0, 0)), i0));
        _mm_storeu_si128(o + 10, select(lane_2, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 2, 2, 2)),
                                        _mm_shuffle_epi32(interior, _MM_SHUFFLE(2, 0, 0, 1))));
        _mm_storeu_si128(o + 11, _mm_shuffle_epi32(interior, _MM_SHUFFLE(2, 1, 0, 1)));
    }
}
#endif

}  // namespace

void write_grandchild_faces(const Topology& p, int f0, int f1, Index* out) {
    // The places spare a read of each edge's ends from far away (docs/benchmark.md, "Measurements behind the code").
    if (p.face_edge_places.empty()) return grandchild_faces<false>(p, f0, f1, out);
#if defined(__SSE2__)
    const int vector_end = std::clamp(p.num_faces() - 1, f0, f1);  // the vector loads read into the next face
    grandchild_faces_sse2(p, f0, vector_end, out);
    f0 = vector_end;
#endif
    grandchild_faces<true>(p, f0, f1, out);
}

}  // namespace loopsub::detail
