// AVX2 + FMA kernel: the masks of the scalar reference (kernels_scalar.cpp), two ways depending on the input.
//
// Quads (kernels_quads.h; the fast path): SIMD across channels, two outputs per 256-bit register. A neighbour's
// four channels are one 16-byte load; the low half of a register works on output i and the high half on output
// i + 1. Each lane adds its ring in the reference's order; FMA in the final weighting changes the last bit.
//
// Planar input (element_stride 1): SIMD across outputs, eight at a time, neighbours fetched by gathers driven by
// the index tables; one load of the indices serves the channels of a pass (up to four, so that the accumulators
// stay in registers). A vertex block loops to its largest valence and masks off the lanes whose ring is shorter
// (they add exact zeros). Gathers issue one load per channel per neighbour, which is why quads are faster.
//
// Other layouts run the reference. Special vertices and edges are recomputed afterwards (kernels_specials.h).
#include <immintrin.h>

#include <algorithm>
#include <cstdint>

#include "kernels.h"
#include "kernels_quads.h"
#include "kernels_specials.h"

namespace loopsub::detail {

namespace {

// ---- Quads: two outputs per register ----------------------------------------------------------------------------

// Quad of element `lo` in the low half of the register, of element `hi` in the high half.
template <std::size_t Step>
inline __m256 load_pair(const QuadSource<Step>& in, std::size_t lo, std::size_t hi) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(in.at(lo))), _mm_loadu_ps(in.at(hi)), 1);
}

inline __m256 broadcast_pair(float lo, float hi) { return _mm256_set_m128(_mm_set1_ps(hi), _mm_set1_ps(lo)); }

// Stores the low half to `element`, and the high half to element + 1 when `both`.
inline void store_pair(const PackedQuads& out, std::size_t element, __m256 v, bool both) {
    if (both) _mm256_storeu_ps(out.data + element * kQuad, v);
    else out.store(element, _mm256_castps256_ps128(v));
}

inline void store_pair(const QuadTarget& out, std::size_t element, __m256 v, bool both) {
    out.store(element, _mm256_castps256_ps128(v));
    if (both) out.store(element + 1, _mm256_extractf128_ps(v, 1));
}

// Smooth vertex points i and j (j = i + 1, or j = i for an odd last vertex: then only i is stored).
template <std::size_t Step, typename Out>
inline void vertex_pair(const Tables& t, const QuadSource<Step>& in, const Out& out, int i, int j) {
    const int first_i = t.ring_offsets[i], valence_i = t.ring_offsets[i + 1] - first_i;
    const int first_j = t.ring_offsets[j], valence_j = t.ring_offsets[j + 1] - first_j;
    const int common = std::min(valence_i, valence_j);
    __m256 ring_sum = _mm256_setzero_ps();
    for (int k = 0; k < common; ++k) ring_sum = _mm256_add_ps(ring_sum, load_pair(in, t.ring[first_i + k], t.ring[first_j + k]));
    // The longer ring's tail; the other half adds zeros.
    const __m128 zero = _mm_setzero_ps();
    for (int k = common; k < valence_i; ++k)
        ring_sum = _mm256_add_ps(ring_sum, _mm256_set_m128(zero, _mm_loadu_ps(in.at(t.ring[first_i + k]))));
    for (int k = common; k < valence_j; ++k)
        ring_sum = _mm256_add_ps(ring_sum, _mm256_set_m128(_mm_loadu_ps(in.at(t.ring[first_j + k])), zero));

    const __m256 w_self = broadcast_pair(t.smooth_self[valence_i], t.smooth_self[valence_j]);
    const __m256 w_ring = broadcast_pair(t.smooth_ring[valence_i], t.smooth_ring[valence_j]);
    store_pair(out, i, _mm256_fmadd_ps(w_ring, ring_sum, _mm256_mul_ps(w_self, load_pair(in, i, j))), j != i);
}

// Smooth edge points e and f (f = e + 1, or f = e for an odd last edge).
template <std::size_t Step, typename Out>
inline void edge_pair(const Tables& t, const QuadSource<Step>& in, const Out& out, int e, int f) {
    const __m256 ends = _mm256_add_ps(load_pair(in, t.edge_a[e], t.edge_a[f]), load_pair(in, t.edge_b[e], t.edge_b[f]));
    const __m256 wings = _mm256_add_ps(load_pair(in, t.edge_c[e], t.edge_c[f]), load_pair(in, t.edge_d[e], t.edge_d[f]));
    const __m256 point = _mm256_fmadd_ps(_mm256_set1_ps(kSmoothEdgeEndWeight), ends,
                                         _mm256_mul_ps(_mm256_set1_ps(kSmoothEdgeWingWeight), wings));
    store_pair(out, t.first_edge_point + e, point, f != e);
}

// One quad of every smooth vertex and edge point of the ranges; Out is PackedQuads or QuadTarget.
template <std::size_t Step, typename Out>
void smooth_quad(const Tables& t, const QuadSource<Step> in, const Out out, Range vertices, Range edges) {
    int i = vertices.begin;
    for (; i + 1 < vertices.end; i += 2) vertex_pair(t, in, out, i, i + 1);
    if (i < vertices.end) vertex_pair(t, in, out, i, i);
    int e = edges.begin;
    for (; e + 1 < edges.end; e += 2) edge_pair(t, in, out, e, e + 1);
    if (e < edges.end) edge_pair(t, in, out, e, e);
}

// ---- Planar input: eight outputs per register, gathers ---------------------------------------------------------

constexpr int kLanes = 8;
constexpr int kMaxPass = 4;  // channels per pass

template <int G>
struct PlanarPass {
    const float* in[G];  // channel starts; element stride 1
    float* out[G];
    std::size_t out_step;
};

inline __m256i iota() { return _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7); }

// Eight consecutive indices; a partial block reads only its own lanes and gets zeros (a valid index) elsewhere.
template <bool Full>
inline __m256i load_indices(const std::int32_t* p, __m256i lanes) {
    if constexpr (Full) return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p));
    return _mm256_maskload_epi32(p, lanes);
}

inline int horizontal_max(__m256i v) {
    __m128i m = _mm_max_epi32(_mm256_castsi256_si128(v), _mm256_extracti128_si256(v, 1));
    m = _mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(1, 0, 3, 2)));
    m = _mm_max_epi32(m, _mm_shuffle_epi32(m, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm_cvtsi128_si32(m);
}

// Writes lanes [0, n) to elements [i, i + n): a plain store for planar output, lane by lane otherwise.
template <bool Full>
inline void store_lanes(float* q, std::size_t step, std::size_t i, __m256 v, __m256i lanes, int n) {
    if (step == 1) {
        if constexpr (Full) _mm256_storeu_ps(q + i, v);
        else _mm256_maskstore_ps(q + i, lanes, v);
        return;
    }
    alignas(32) float lane_values[kLanes];
    _mm256_store_ps(lane_values, v);
    for (int j = 0; j < n; ++j) q[(i + j) * step] = lane_values[j];
}

// Smooth vertex points [i, i + n), n <= 8.
template <int G, bool Full>
inline void vertex_block(const Tables& t, const PlanarPass<G>& pass, int i, int n) {
    const __m256i lanes = Full ? _mm256_set1_epi32(-1) : _mm256_cmpgt_epi32(_mm256_set1_epi32(n), iota());
    const __m256i first = load_indices<Full>(t.ring_offsets + i, lanes);
    const __m256i valence = _mm256_sub_epi32(load_indices<Full>(t.ring_offsets + i + 1, lanes), first);
    const int max_valence = horizontal_max(valence);

    __m256 ring_sum[G];
    for (int g = 0; g < G; ++g) ring_sum[g] = _mm256_setzero_ps();
    for (int k = 0; k < max_valence; ++k) {
        const __m256i live = _mm256_cmpgt_epi32(valence, _mm256_set1_epi32(k));
        const __m256i neighbour = _mm256_mask_i32gather_epi32(_mm256_setzero_si256(), t.ring,
                                                              _mm256_add_epi32(first, _mm256_set1_epi32(k)), live, 4);
        for (int g = 0; g < G; ++g) {
            ring_sum[g] = _mm256_add_ps(ring_sum[g], _mm256_mask_i32gather_ps(_mm256_setzero_ps(), pass.in[g], neighbour,
                                                                              _mm256_castsi256_ps(live), 4));
        }
    }
    // Padding lanes have valence 0, whose weights exist (copy the vertex).
    const __m256 w_self = _mm256_i32gather_ps(t.smooth_self, valence, 4);
    const __m256 w_ring = _mm256_i32gather_ps(t.smooth_ring, valence, 4);
    for (int g = 0; g < G; ++g) {
        const __m256 own = Full ? _mm256_loadu_ps(pass.in[g] + i) : _mm256_maskload_ps(pass.in[g] + i, lanes);
        store_lanes<Full>(pass.out[g], pass.out_step, i, _mm256_fmadd_ps(w_ring, ring_sum[g], _mm256_mul_ps(w_self, own)),
                          lanes, n);
    }
}

// Smooth edge points [e, e + n), n <= 8.
template <int G, bool Full>
inline void edge_block(const Tables& t, const PlanarPass<G>& pass, int e, int n) {
    const __m256i lanes = Full ? _mm256_set1_epi32(-1) : _mm256_cmpgt_epi32(_mm256_set1_epi32(n), iota());
    const __m256i a = load_indices<Full>(t.edge_a + e, lanes), b = load_indices<Full>(t.edge_b + e, lanes);
    const __m256i c = load_indices<Full>(t.edge_c + e, lanes), d = load_indices<Full>(t.edge_d + e, lanes);
    const std::size_t target = t.first_edge_point + e;
    for (int g = 0; g < G; ++g) {
        const float* p = pass.in[g];
        const __m256 ends = _mm256_add_ps(_mm256_i32gather_ps(p, a, 4), _mm256_i32gather_ps(p, b, 4));
        const __m256 wings = _mm256_add_ps(_mm256_i32gather_ps(p, c, 4), _mm256_i32gather_ps(p, d, 4));
        const __m256 point = _mm256_fmadd_ps(_mm256_set1_ps(kSmoothEdgeEndWeight), ends,
                                             _mm256_mul_ps(_mm256_set1_ps(kSmoothEdgeWingWeight), wings));
        store_lanes<Full>(pass.out[g], pass.out_step, target, point, lanes, n);
    }
}

template <int G>
void smooth_planar(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out, int c0,
                   Range vertices, Range edges) {
    PlanarPass<G> pass;
    for (int g = 0; g < G; ++g) {
        pass.in[g] = in.data + (c0 + g) * in.channel_stride;
        pass.out[g] = out.data + (c0 + g) * out.channel_stride;
    }
    pass.out_step = out.element_stride;
    const Tables t(s);
    int i = vertices.begin;
    for (; i + kLanes <= vertices.end; i += kLanes) vertex_block<G, true>(t, pass, i, kLanes);
    if (i < vertices.end) vertex_block<G, false>(t, pass, i, vertices.end - i);
    int e = edges.begin;
    for (; e + kLanes <= edges.end; e += kLanes) edge_block<G, true>(t, pass, e, kLanes);
    if (e < edges.end) edge_block<G, false>(t, pass, e, edges.end - e);
}

}  // namespace

void refine_avx2(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out, Range vertices,
                 Range edges) {
    if (reads_as_quads(in)) {
        const Tables tables(s);
        for (int quad = 0; quad * kQuad < in.num_channels; ++quad) {
            const float* first_channel = in.data + quad * kQuad;
            const QuadTarget target = quad_target(out, quad);
            if (in.element_stride == kQuad && target.packed())
                smooth_quad(tables, QuadSource<kQuad>{first_channel, kQuad}, PackedQuads{target.data}, vertices, edges);
            else if (in.element_stride == kQuad)
                smooth_quad(tables, QuadSource<kQuad>{first_channel, kQuad}, target, vertices, edges);
            else
                smooth_quad(tables, QuadSource<0>{first_channel, in.element_stride}, target, vertices, edges);
        }
    } else if (in.element_stride == 1) {
        for (int c0 = 0; c0 < in.num_channels; c0 += kMaxPass) {
            switch (std::min(kMaxPass, in.num_channels - c0)) {
                case 1: smooth_planar<1>(s, in, out, c0, vertices, edges); break;
                case 2: smooth_planar<2>(s, in, out, c0, vertices, edges); break;
                case 3: smooth_planar<3>(s, in, out, c0, vertices, edges); break;
                default: smooth_planar<4>(s, in, out, c0, vertices, edges); break;
            }
        }
    } else {
        return refine_scalar(s, in, out, vertices, edges);
    }
    apply_specials(s, in, out, vertices, edges);
}

}  // namespace loopsub::detail
