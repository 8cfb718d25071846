// AVX2 + FMA kernel: the masks of the scalar reference (kernels_scalar.cpp) on input in quads (kernels_quads.h),
// the layout Plan::evaluate refines in. SIMD runs across channels, two outputs per 256-bit register: a
// neighbour's four channels are one 16-byte load; the low half of a register works on output i and the high half
// on output i + 1. Each lane adds its ring in the reference's order; FMA in the final weighting changes the last
// bit. (Gathers across eight outputs from planar arrays were measured slower: one load per channel and neighbour;
// docs/benchmark.md.) Other layouts run the reference. Special vertices and edges are recomputed
// afterwards (kernels_specials.h).
#include <immintrin.h>

#include <algorithm>
#include <cstdint>
#include <type_traits>

#include "kernels/kernels.h"
#include "kernels/kernels_limit.h"
#include "kernels/kernels_patch.h"
#include "kernels/kernels_quads.h"
#include "kernels/kernels_specials.h"

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

// Both: the low half's four lanes, whose last lands on element + 1's first channel, then the high half's three over it.
inline void store_pair(const PackedRows3& out, std::size_t element, __m256 v, bool both) {
    if (!both) return out.store(element, _mm256_castps256_ps128(v));
    _mm_storeu_ps(out.data + element * 3, _mm256_castps256_ps128(v));
    out.store(element + 1, _mm256_extractf128_ps(v, 1));
}

inline void store_pair(const QuadTarget& out, std::size_t element, __m256 v, bool both) {
    out.store(element, _mm256_castps256_ps128(v));
    if (both) out.store(element + 1, _mm256_extractf128_ps(v, 1));
}

// Four rows of three from two pairs (points 0, 1 in `first`, 2, 3 in `second`).
inline void store_two_pairs(const PackedRows3& out, std::size_t element, __m256 first, __m256 second) {
    out.store_four(element, _mm256_castps256_ps128(first), _mm256_extractf128_ps(first, 1),
                   _mm256_castps256_ps128(second), _mm256_extractf128_ps(second, 1));
}

// Smooth vertex points i and j (j = i + 1, or j = i for an odd last vertex).
template <std::size_t Step>
inline __m256 vertex_pair(const Tables& t, const QuadSource<Step>& in, int i, int j) {
    const int first_i = t.ring_first(i), valence_i = t.valence(i);
    const int first_j = t.ring_first(j), valence_j = t.valence(j);
    const int common = std::min(valence_i, valence_j);
    __m256 ring_sum = _mm256_setzero_ps();
    int k = 0;
    for (; k + 1 < common; k += 2) {
        std::int32_t i0, i1, j0, j1;
        load_index_pair(t.ring + first_i + k, i0, i1);
        load_index_pair(t.ring + first_j + k, j0, j1);
        ring_sum = _mm256_add_ps(ring_sum, load_pair(in, i0, j0));
        ring_sum = _mm256_add_ps(ring_sum, load_pair(in, i1, j1));
    }
    if (k < common) ring_sum = _mm256_add_ps(ring_sum, load_pair(in, t.ring[first_i + k], t.ring[first_j + k]));
    // The longer ring's tail; the other half adds zeros.
    const __m128 zero = _mm_setzero_ps();
    for (int k = common; k < valence_i; ++k)
        ring_sum = _mm256_add_ps(ring_sum, _mm256_set_m128(zero, _mm_loadu_ps(in.at(t.ring[first_i + k]))));
    for (int k = common; k < valence_j; ++k)
        ring_sum = _mm256_add_ps(ring_sum, _mm256_set_m128(_mm_loadu_ps(in.at(t.ring[first_j + k])), zero));

    const __m256 w_self = broadcast_pair(t.smooth_self[valence_i], t.smooth_self[valence_j]);
    const __m256 w_ring = broadcast_pair(t.smooth_ring[valence_i], t.smooth_ring[valence_j]);
    return _mm256_fmadd_ps(w_ring, ring_sum, _mm256_mul_ps(w_self, load_pair(in, i, j)));
}

// Smooth edge points e and f (f = e + 1, or f = e for an odd last edge).
template <std::size_t Step>
inline __m256 edge_pair(const Tables& t, const QuadSource<Step>& in, int e, int f) {
    const __m256 ends = _mm256_add_ps(load_pair(in, t.end(e, 0), t.end(f, 0)), load_pair(in, t.end(e, 1), t.end(f, 1)));
    const __m256 wings =
        _mm256_add_ps(load_pair(in, t.wing_c(e), t.wing_c(f)), load_pair(in, t.wing_d(e), t.wing_d(f)));
    return _mm256_fmadd_ps(_mm256_set1_ps(kSmoothEdgeEndWeight), ends,
                           _mm256_mul_ps(_mm256_set1_ps(kSmoothEdgeWingWeight), wings));
}

// edge_pair for edges e and e + 1, their indices read a pair at a time.
template <std::size_t Step>
inline __m256 next_edges_pair(const Tables& t, const QuadSource<Step>& in, int e) {
    const EdgePairIndices i = next_edges_indices(t, e);
    const __m256 sum_ends = _mm256_add_ps(load_pair(in, i.a[0], i.a[1]), load_pair(in, i.b[0], i.b[1]));
    const __m256 wings = _mm256_add_ps(load_pair(in, i.c[0], i.c[1]), load_pair(in, i.d[0], i.d[1]));
    return _mm256_fmadd_ps(_mm256_set1_ps(kSmoothEdgeEndWeight), sum_ends,
                           _mm256_mul_ps(_mm256_set1_ps(kSmoothEdgeWingWeight), wings));
}

// The pairs' arithmetic on one point (the fans, the interior edges): the same bits per lane.
// Lambdas, so that the passes given them as arguments inline them (as function pointers they were not, and slower).
constexpr auto smooth_vertex = [](__m128 self, __m128 ring_sum, float w_self, float w_ring) {
    return _mm_fmadd_ps(_mm_set1_ps(w_ring), ring_sum, _mm_mul_ps(_mm_set1_ps(w_self), self));
};
constexpr auto smooth_edge = [](__m128 a, __m128 b, __m128 c, __m128 d) {
    return _mm_fmadd_ps(_mm_set1_ps(kSmoothEdgeEndWeight), _mm_add_ps(a, b),
                        _mm_mul_ps(_mm_set1_ps(kSmoothEdgeWingWeight), _mm_add_ps(c, d)));
};

// A step of a tangent's sum (kernels_limit.h).
constexpr auto multiply_add = [](__m128 w, __m128 d, __m128 sum) { return _mm_fmadd_ps(w, d, sum); };

// Eight rows of three floats, x0 y0 z0 x1 ... z7, in three 32-byte stores, from the lanes of x, y and z: to_x, to_y and
// to_z permute each coordinate so that its lanes are where the stores want them (x at 0, 3, 6 of the first, 1, 4, 7 of
// the second, 2, 5 of the third; y and z in turn after it), which blends then pick.
void store_eight_rows(float* rows, __m256 x, __m256 y, __m256 z, __m256i to_x, __m256i to_y, __m256i to_z) {
    const __m256 px = _mm256_permutevar8x32_ps(x, to_x), py = _mm256_permutevar8x32_ps(y, to_y),
                 pz = _mm256_permutevar8x32_ps(z, to_z);
    constexpr int k147 = 0x92, k25 = 0x24;  // lanes 1, 4, 7 and lanes 2, 5
    _mm256_storeu_ps(rows, _mm256_blend_ps(_mm256_blend_ps(px, py, k147), pz, k25));
    _mm256_storeu_ps(rows + 8, _mm256_blend_ps(_mm256_blend_ps(pz, px, k147), py, k25));
    _mm256_storeu_ps(rows + 16, _mm256_blend_ps(_mm256_blend_ps(py, pz, k147), px, k25));
}

// The unit normals t1 x t2 of eight tangent pairs (x, y, z in a quad's first lanes), as eight rows of three at `rows`:
// the tangents turned into x, y and z registers of eight lanes, the reference's float arithmetic (limit_normals.h)
// with fused multiply-adds, zero where the tangents do not span a plane.
struct UnitNormals {
    static constexpr int kWidth = 8;

    // x, y, z of tangents t[0 .. 7] in the lanes of vertices 0, 2, 4, 6, 1, 3, 5, 7: two neighbours per 32-byte load,
    // and no lane crossing.
    static void across(const __m128* t, __m256& x, __m256& y, __m256& z) {
        const float* p = reinterpret_cast<const float*>(t);
        const __m256 t01 = _mm256_loadu_ps(p), t23 = _mm256_loadu_ps(p + 8);
        const __m256 t45 = _mm256_loadu_ps(p + 16), t67 = _mm256_loadu_ps(p + 24);
        // Per 128-bit lane: x0 x2 y0 y2 | x1 x3 y1 y3, and z0 z2 .. | z1 z3 ..; then the same of 4 to 7.
        const __m256 xy_0123 = _mm256_unpacklo_ps(t01, t23), z_0123 = _mm256_unpackhi_ps(t01, t23);
        const __m256 xy_4567 = _mm256_unpacklo_ps(t45, t67), z_4567 = _mm256_unpackhi_ps(t45, t67);
        x = _mm256_shuffle_ps(xy_0123, xy_4567, _MM_SHUFFLE(1, 0, 1, 0));
        y = _mm256_shuffle_ps(xy_0123, xy_4567, _MM_SHUFFLE(3, 2, 3, 2));
        z = _mm256_shuffle_ps(z_0123, z_4567, _MM_SHUFFLE(1, 0, 1, 0));
    }

    // Eight rows x0 y0 z0 x1 ... z7 from across()'s lanes.
    static void store_rows(float* rows, __m256 x, __m256 y, __m256 z) {
        store_eight_rows(rows, x, y, z, _mm256_setr_epi32(0, 5, 3, 4, 2, 7, 1, 6),
                         _mm256_setr_epi32(6, 0, 5, 3, 4, 2, 7, 1), _mm256_setr_epi32(1, 6, 0, 5, 3, 4, 2, 7));
    }

    // The cross product of tangents a and b, and its squared length.
    static __m256 cross(const __m256 a[3], const __m256 b[3], __m256 n[3]) {
        n[0] = _mm256_fmsub_ps(a[1], b[2], _mm256_mul_ps(a[2], b[1]));
        n[1] = _mm256_fmsub_ps(a[2], b[0], _mm256_mul_ps(a[0], b[2]));
        n[2] = _mm256_fmsub_ps(a[0], b[1], _mm256_mul_ps(a[1], b[0]));
        return _mm256_fmadd_ps(n[0], n[0], _mm256_fmadd_ps(n[1], n[1], _mm256_mul_ps(n[2], n[2])));
    }

    // t scaled by a power of two to a largest coordinate near one (limit_normals.cpp, scale_to_unit).
    static void scale_to_unit(__m256 t[3]) {
        const __m256 sign = _mm256_set1_ps(-0.0f);
        const __m256 largest = _mm256_max_ps(_mm256_andnot_ps(sign, t[0]),
                                             _mm256_max_ps(_mm256_andnot_ps(sign, t[1]), _mm256_andnot_ps(sign, t[2])));
        const __m256i exponent =
            _mm256_min_epi32(_mm256_and_si256(_mm256_castps_si256(largest), _mm256_set1_epi32(0x7f800000)),
                             _mm256_set1_epi32(252 << 23));
        const __m256 scale = _mm256_castsi256_ps(_mm256_sub_epi32(_mm256_set1_epi32(253 << 23), exponent));
        for (int c = 0; c < 3; ++c) t[c] = _mm256_mul_ps(t[c], scale);
    }

    void operator()(const __m128* t1, const __m128* t2, float* rows) const {
        __m256 a[3], b[3], n[3];
        across(t1, a[0], a[1], a[2]);
        across(t2, b[0], b[1], b[2]);
        __m256 squared = cross(a, b, n);
        const __m256 in_range = _mm256_and_ps(_mm256_cmp_ps(squared, _mm256_set1_ps(kLeastSquaredLength), _CMP_GE_OQ),
                                              _mm256_cmp_ps(squared, _mm256_set1_ps(kMostSquaredLength), _CMP_LE_OQ));
        if (_mm256_movemask_ps(in_range) != 0xff) {  // rare; no bits change in the lanes in range
            scale_to_unit(a);
            scale_to_unit(b);
            squared = cross(a, b, n);
        }
        const __m256 positive = _mm256_cmp_ps(squared, _mm256_setzero_ps(), _CMP_GT_OQ);
        const __m256 inverse = _mm256_and_ps(positive, _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(squared)));
        store_rows(rows, _mm256_mul_ps(n[0], inverse), _mm256_mul_ps(n[1], inverse), _mm256_mul_ps(n[2], inverse));
    }
};
constexpr UnitNormals unit_normals;

// RegularLimit (kernels_limit.h) for two vertices at once, a register half each, into consecutive slots of a chunk:
// its arithmetic per half, so the same bits (smooth_vertex's weighting, multiply_add's steps).
template <typename Regular>
struct BothInOne {
    __m256 a, b, c, w_self, w_ring;

    explicit BothInOne(const Regular& r)
        : a(_mm256_set_m128(r.a, r.a)),
          b(_mm256_set_m128(r.b, r.b)),
          c(_mm256_set_m128(r.c, r.c)),
          w_self(_mm256_set1_ps(r.w_self)),
          w_ring(_mm256_set1_ps(r.w_ring)) {}

    void operator()(__m128 centre_a, const __m128 ring_a[6], __m128 centre_b, const __m128 ring_b[6], LimitChunk& chunk,
                    int slot) const {
        __m256 p[6];
        for (int k = 0; k < 6; ++k) p[k] = _mm256_set_m128(ring_b[k], ring_a[k]);
        __m256 ring_sum = _mm256_setzero_ps();
        for (int k = 0; k < 6; ++k) ring_sum = _mm256_add_ps(ring_sum, p[k]);
        __m256 t1 = _mm256_mul_ps(a, _mm256_sub_ps(p[0], p[3]));
        t1 = _mm256_fmadd_ps(b, _mm256_sub_ps(p[1], p[2]), t1);
        t1 = _mm256_fmadd_ps(b, _mm256_sub_ps(p[5], p[4]), t1);
        const __m256 t2 = _mm256_fmadd_ps(c, _mm256_sub_ps(p[2], p[5]), _mm256_mul_ps(c, _mm256_sub_ps(p[1], p[4])));
        const __m256 position =
            _mm256_fmadd_ps(w_ring, ring_sum, _mm256_mul_ps(w_self, _mm256_set_m128(centre_b, centre_a)));
        _mm256_storeu_ps(reinterpret_cast<float*>(chunk.position + slot), position);
        _mm256_storeu_ps(reinterpret_cast<float*>(chunk.t1 + slot), t1);
        _mm256_storeu_ps(reinterpret_cast<float*>(chunk.t2 + slot), t2);
    }
};

// One quad of every smooth vertex and edge point of the ranges; Out is PackedQuads, PackedRows3 or QuadTarget. Rows
// of three (the last level's positions) go four points at a time (PackedRows3::store_four).
template <std::size_t Step, typename Out>
void smooth_quad(const Tables& t, const QuadSource<Step> in, const Out out, Range vertices, Range edges) {
    int i = vertices.begin, e = edges.begin;
    if constexpr (std::is_same_v<Out, PackedRows3>) {
        for (; i + 3 < vertices.end; i += 4)
            store_two_pairs(out, i, vertex_pair(t, in, i, i + 1), vertex_pair(t, in, i + 2, i + 3));
        for (; e + 3 < edges.end; e += 4)
            store_two_pairs(out, t.first_edge_point + e, next_edges_pair(t, in, e), next_edges_pair(t, in, e + 2));
    }
    for (; i + 1 < vertices.end; i += 2) store_pair(out, i, vertex_pair(t, in, i, i + 1), true);
    if (i < vertices.end) store_pair(out, i, vertex_pair(t, in, i, i), false);
    for (; e + 1 < edges.end; e += 2) store_pair(out, t.first_edge_point + e, next_edges_pair(t, in, e), true);
    if (e < edges.end) store_pair(out, t.first_edge_point + e, edge_pair(t, in, e, e), false);
}

}  // namespace

void refine_avx2(const LevelStencils& s, const StencilView& view, ChannelsView<const float> in, ChannelsView<float> out,
                 Range vertices, Range edges) {
    if (!reads_as_quads(in)) return refine_scalar(s, view, in, out, vertices, edges);
    for_each_quad(s, view, in, out, [&](const Tables& tables, auto source, auto target) {
        smooth_quad(tables, source, target, vertices, edges);
    });
    apply_specials(s, view, in, out, vertices, edges);
}

void refine_fans_avx2(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out,
                      Range parent_edges) {
    if (!reads_as_quads(in)) return refine_fans_scalar(s, in, out, parent_edges);
    const int nv = s.fan_first_midpoint;
    for_each_quad(s, stored_view(s), in, out, [&](const Tables& t, auto source, auto target) {
        auto irregular = [&](int h) {
            const int i = nv + h;
            target.store(std::size_t(i), _mm256_castps256_ps128(vertex_pair(t, source, i, i)));
            target.store(t.first_edge_point + 2 * std::size_t(h),
                         _mm256_castps256_ps128(edge_pair(t, source, 2 * h, 2 * h)));
            target.store(t.first_edge_point + 2 * std::size_t(h) + 1,
                         _mm256_castps256_ps128(edge_pair(t, source, 2 * h + 1, 2 * h + 1)));
        };
        fan_quad(t, s, source, target, parent_edges, smooth_vertex, smooth_edge, irregular);
    });
    apply_specials(s, stored_view(s), in, out, {nv + parent_edges.begin, nv + parent_edges.end},
                   {2 * parent_edges.begin, 2 * parent_edges.end});
}

void limit_avx2(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in, ChannelsView<float> out,
                float* normals, Range vertices) {
    limit_pass(lt, view, in, out, normals, vertices, smooth_vertex, multiply_add, unit_normals,
               [](const Tables& t, auto source, auto target, Range v) {
                   smooth_quad(t, source, target, v, {0, 0});
               });
}

void limit_grandchild_avx2(const LimitTables& lt, ChannelsView<const float> in, ChannelsView<float> out, float* normals,
                           GrandchildShare share) {
    grandchild_limit_pass<BothInOne>(lt, in, out, normals, share, smooth_vertex, multiply_add, unit_normals,
                                     limit_avx2);
}

void refine_interior_avx2(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out, Range faces) {
    if (!reads_as_quads(in)) return refine_interior_scalar(s, in, out, faces);
    for_each_quad(s, stored_view(s), in, out, [&](const Tables&, auto source, auto target) {
        interior_quad(s, source, target, faces, smooth_edge);
    });
}

// The patch kernel (kernels_patch.h) eight samples at a time, with fused multiply-adds.
struct PatchAvx2 {
    using Vec = __m256;
    static constexpr int kWidth = 8;
    static Vec load(const float* p) { return _mm256_loadu_ps(p); }
    static Vec broadcast(float x) { return _mm256_set1_ps(x); }
    static Vec multiply_add(Vec a, Vec b, Vec c) { return _mm256_fmadd_ps(a, b, c); }
    static Vec multiply(Vec a, Vec b) { return _mm256_mul_ps(a, b); }
    static Vec subtract(Vec a, Vec b) { return _mm256_sub_ps(a, b); }
    static Vec unit_factor(Vec x) {
        const Vec positive = _mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_GT_OQ);
        return _mm256_and_ps(positive, _mm256_div_ps(_mm256_set1_ps(1.0f), _mm256_sqrt_ps(x)));
    }
    static Vec max_magnitude(Vec a, Vec b, Vec c) {
        const Vec sign = _mm256_set1_ps(-0.0f);
        return _mm256_max_ps(_mm256_andnot_ps(sign, a),
                             _mm256_max_ps(_mm256_andnot_ps(sign, b), _mm256_andnot_ps(sign, c)));
    }
    static Vec reciprocal_or_zero(Vec x) {
        return _mm256_and_ps(_mm256_cmp_ps(x, _mm256_setzero_ps(), _CMP_GT_OQ), _mm256_div_ps(_mm256_set1_ps(1.0f), x));
    }
    static void store(float* p, Vec v) { _mm256_storeu_ps(p, v); }
    static void store_rows(float* rows, Vec x, Vec y, Vec z) {  // the lanes in row order
        store_eight_rows(rows, x, y, z, _mm256_setr_epi32(0, 3, 6, 1, 4, 7, 2, 5),
                         _mm256_setr_epi32(5, 0, 3, 6, 1, 4, 7, 2), _mm256_setr_epi32(2, 5, 0, 3, 6, 1, 4, 7));
    }
};

void patch_avx2(const float points[kPatchPoints][4], const float* weights, int count, int stride, float* positions,
                float* normals) {
    patch_pass<PatchAvx2>(points, weights, count, stride, positions, normals);
}

}  // namespace loopsub::detail
