// SSE4.1 kernel: the masks of the scalar reference (kernels_scalar.cpp), four channels at a time.
//
// SIMD runs across channels: with the input in quads (kernels_quads.h) one 16-byte load fetches a neighbour's
// x, y, z and a fourth channel, and each vertex or edge point is one short loop of loads and adds in the
// reference's order (SSE4.1 has no FMA: the results equal the reference bit for bit). Other input layouts run the
// reference itself: SSE4.1 has no gather, and vectors built across outputs from planar data (a load and an insert
// per lane and channel) measured slower than the scalar code.
// Special vertices and edges (creases, corners, boundaries) are recomputed afterwards (kernels_specials.h).
#include <smmintrin.h>

#include <type_traits>

#include "kernels/kernels.h"
#include "kernels/kernels_limit.h"
#include "kernels/kernels_patch.h"
#include "kernels/kernels_quads.h"
#include "kernels/kernels_specials.h"

namespace loopsub::detail {

namespace {

// The smooth masks' arithmetic on one point, shared by the table passes, the fans and the interior edges.
// Lambdas, so that the passes given them as arguments inline them (as function pointers they were not, and slower).
constexpr auto smooth_vertex = [](__m128 self, __m128 ring_sum, float w_self, float w_ring) {
    return _mm_add_ps(_mm_mul_ps(_mm_set1_ps(w_self), self), _mm_mul_ps(_mm_set1_ps(w_ring), ring_sum));
};
constexpr auto smooth_edge = [](__m128 a, __m128 b, __m128 c, __m128 d) {
    return _mm_add_ps(_mm_mul_ps(_mm_set1_ps(kSmoothEdgeEndWeight), _mm_add_ps(a, b)),
                      _mm_mul_ps(_mm_set1_ps(kSmoothEdgeWingWeight), _mm_add_ps(c, d)));
};

template <std::size_t Step>
inline __m128 vertex_point(const Tables& t, const QuadSource<Step>& in, int i) {
    const int first = t.ring_first(i), valence = t.valence(i), last = first + valence;
    __m128 ring_sum = _mm_setzero_ps();
    int k = first;
    for (; k + 1 < last; k += 2) {
        std::int32_t at_k, at_next;
        load_index_pair(t.ring + k, at_k, at_next);
        ring_sum = _mm_add_ps(ring_sum, _mm_loadu_ps(in.at(at_k)));
        ring_sum = _mm_add_ps(ring_sum, _mm_loadu_ps(in.at(at_next)));
    }
    if (k < last) ring_sum = _mm_add_ps(ring_sum, _mm_loadu_ps(in.at(t.ring[k])));
    return smooth_vertex(_mm_loadu_ps(in.at(i)), ring_sum, t.smooth_self[valence], t.smooth_ring[valence]);
}

template <std::size_t Step>
inline __m128 edge_point(const Tables& t, const QuadSource<Step>& in, int e) {
    return smooth_edge(_mm_loadu_ps(in.at(t.end(e, 0))), _mm_loadu_ps(in.at(t.end(e, 1))),
                       _mm_loadu_ps(in.at(t.wing_c(e))), _mm_loadu_ps(in.at(t.wing_d(e))));
}

// Edge points e and e + 1, their indices read a pair at a time.
template <std::size_t Step>
inline void next_edge_points(const Tables& t, const QuadSource<Step>& in, int e, __m128& first, __m128& second) {
    const EdgePairIndices i = next_edges_indices(t, e);
    auto point = [&](int k) {
        return smooth_edge(_mm_loadu_ps(in.at(i.a[k])), _mm_loadu_ps(in.at(i.b[k])), _mm_loadu_ps(in.at(i.c[k])),
                           _mm_loadu_ps(in.at(i.d[k])));
    };
    first = point(0);
    second = point(1);
}

// A step of a tangent's sum (kernels_limit.h): the reference's multiply, then add.
constexpr auto multiply_add = [](__m128 w, __m128 d, __m128 sum) { return _mm_add_ps(sum, _mm_mul_ps(w, d)); };

// Four rows of three floats, x0 y0 z0 x1 ... z3, from the lanes of x, y and z: transposed into quads, stored in three.
void store_four_rows(float* rows, __m128 x, __m128 y, __m128 z) {
    __m128 unused = _mm_setzero_ps();
    _MM_TRANSPOSE4_PS(x, y, z, unused);
    PackedRows3{rows}.store_four(0, x, y, z, unused);
}

// The unit normals t1 x t2 of four tangent pairs (x, y, z in a quad's first lanes), as four rows of three at `rows`:
// the reference's float arithmetic per lane (limit_normals.cpp), zero where the tangents do not span a plane.
struct UnitNormals {
    static constexpr int kWidth = 4;

    // The cross product of tangents a and b, and its squared length.
    static __m128 cross(const __m128 a[3], const __m128 b[3], __m128 n[3]) {
        n[0] = _mm_sub_ps(_mm_mul_ps(a[1], b[2]), _mm_mul_ps(a[2], b[1]));
        n[1] = _mm_sub_ps(_mm_mul_ps(a[2], b[0]), _mm_mul_ps(a[0], b[2]));
        n[2] = _mm_sub_ps(_mm_mul_ps(a[0], b[1]), _mm_mul_ps(a[1], b[0]));
        return _mm_add_ps(_mm_add_ps(_mm_mul_ps(n[0], n[0]), _mm_mul_ps(n[1], n[1])), _mm_mul_ps(n[2], n[2]));
    }

    // t scaled by a power of two to a largest coordinate near one (limit_normals.cpp, scale_to_unit).
    static void scale_to_unit(__m128 t[3]) {
        const __m128 sign = _mm_set1_ps(-0.0f);
        const __m128 largest =
            _mm_max_ps(_mm_andnot_ps(sign, t[0]), _mm_max_ps(_mm_andnot_ps(sign, t[1]), _mm_andnot_ps(sign, t[2])));
        const __m128i exponent = _mm_min_epi32(_mm_and_si128(_mm_castps_si128(largest), _mm_set1_epi32(0x7f800000)),
                                               _mm_set1_epi32(252 << 23));
        const __m128 scale = _mm_castsi128_ps(_mm_sub_epi32(_mm_set1_epi32(253 << 23), exponent));
        for (int c = 0; c < 3; ++c) t[c] = _mm_mul_ps(t[c], scale);
    }

    void operator()(const __m128* t1, const __m128* t2, float* rows) const {
        __m128 a[4] = {t1[0], t1[1], t1[2], t1[3]}, b[4] = {t2[0], t2[1], t2[2], t2[3]}, n[3];
        _MM_TRANSPOSE4_PS(a[0], a[1], a[2], a[3]);
        _MM_TRANSPOSE4_PS(b[0], b[1], b[2], b[3]);
        __m128 squared = cross(a, b, n);
        const __m128 in_range = _mm_and_ps(_mm_cmpge_ps(squared, _mm_set1_ps(kLeastSquaredLength)),
                                           _mm_cmple_ps(squared, _mm_set1_ps(kMostSquaredLength)));
        if (_mm_movemask_ps(in_range) != 0xf) {  // rare; no bits change in the lanes in range
            scale_to_unit(a);
            scale_to_unit(b);
            squared = cross(a, b, n);
        }
        const __m128 positive = _mm_cmpgt_ps(squared, _mm_setzero_ps());
        const __m128 inverse = _mm_and_ps(positive, _mm_div_ps(_mm_set1_ps(1.0f), _mm_sqrt_ps(squared)));
        store_four_rows(rows, _mm_mul_ps(n[0], inverse), _mm_mul_ps(n[1], inverse), _mm_mul_ps(n[2], inverse));
    }
};
constexpr UnitNormals unit_normals;

// One quad of every smooth vertex and edge point of the ranges; Out is PackedQuads, PackedRows3 or QuadTarget. Rows
// of three (the last level's positions) go four points at a time (PackedRows3::store_four).
template <std::size_t Step, typename Out>
void smooth_quad(const Tables& t, const QuadSource<Step> in, const Out out, Range vertices, Range edges) {
    int i = vertices.begin, e = edges.begin;
    if constexpr (std::is_same_v<Out, PackedRows3>) {
        for (; i + 3 < vertices.end; i += 4)
            out.store_four(i, vertex_point(t, in, i), vertex_point(t, in, i + 1), vertex_point(t, in, i + 2),
                           vertex_point(t, in, i + 3));
        for (; e + 3 < edges.end; e += 4) {
            __m128 p0, p1, p2, p3;
            next_edge_points(t, in, e, p0, p1);
            next_edge_points(t, in, e + 2, p2, p3);
            out.store_four(t.first_edge_point + e, p0, p1, p2, p3);
        }
    }
    for (; i < vertices.end; ++i) out.store(i, vertex_point(t, in, i));
    for (; e < edges.end; ++e) out.store(t.first_edge_point + e, edge_point(t, in, e));
}

}  // namespace

void refine_sse41(const LevelStencils& s, const StencilView& view, ChannelsView<const float> in,
                  ChannelsView<float> out, Range vertices, Range edges) {
    if (!reads_as_quads(in)) return refine_scalar(s, view, in, out, vertices, edges);
    for_each_quad(s, view, in, out, [&](const Tables& tables, auto source, auto target) {
        smooth_quad(tables, source, target, vertices, edges);
    });
    apply_specials(s, view, in, out, vertices, edges);
}

void refine_fans_sse41(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out,
                       Range parent_edges) {
    if (!reads_as_quads(in)) return refine_fans_scalar(s, in, out, parent_edges);
    const int nv = s.fan_first_midpoint;
    for_each_quad(s, stored_view(s), in, out, [&](const Tables& t, auto source, auto target) {
        auto irregular = [&](int h) {
            target.store(std::size_t(nv + h), vertex_point(t, source, nv + h));
            target.store(t.first_edge_point + 2 * std::size_t(h), edge_point(t, source, 2 * h));
            target.store(t.first_edge_point + 2 * std::size_t(h) + 1, edge_point(t, source, 2 * h + 1));
        };
        fan_quad(t, s, source, target, parent_edges, smooth_vertex, smooth_edge, irregular);
    });
    apply_specials(s, stored_view(s), in, out, {nv + parent_edges.begin, nv + parent_edges.end},
                   {2 * parent_edges.begin, 2 * parent_edges.end});
}

void limit_sse41(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in, ChannelsView<float> out,
                 float* normals, Range vertices) {
    limit_pass(lt, view, in, out, normals, vertices, smooth_vertex, multiply_add, unit_normals,
               [](const Tables& t, auto source, auto target, Range v) {
                   smooth_quad(t, source, target, v, {0, 0});
               });
}

void limit_grandchild_sse41(const LimitTables& lt, ChannelsView<const float> in, ChannelsView<float> out,
                            float* normals, GrandchildShare share) {
    grandchild_limit_pass<OneAfterOther>(lt, in, out, normals, share, smooth_vertex, multiply_add, unit_normals,
                                         limit_sse41);
}

void refine_interior_sse41(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out, Range faces) {
    if (!reads_as_quads(in)) return refine_interior_scalar(s, in, out, faces);
    for_each_quad(s, stored_view(s), in, out, [&](const Tables&, auto source, auto target) {
        interior_quad(s, source, target, faces, smooth_edge);
    });
}

// The patch kernel (kernels_patch.h) four samples at a time: multiply then add, as the scalar reference.
struct PatchSse41 {
    using Vec = __m128;
    static constexpr int kWidth = 4;
    static Vec load(const float* p) { return _mm_loadu_ps(p); }
    static Vec broadcast(float x) { return _mm_set1_ps(x); }
    static Vec multiply_add(Vec a, Vec b, Vec c) { return _mm_add_ps(_mm_mul_ps(a, b), c); }
    static Vec multiply(Vec a, Vec b) { return _mm_mul_ps(a, b); }
    static Vec subtract(Vec a, Vec b) { return _mm_sub_ps(a, b); }
    static Vec unit_factor(Vec x) {
        const Vec positive = _mm_cmpgt_ps(x, _mm_setzero_ps());
        return _mm_and_ps(positive, _mm_div_ps(_mm_set1_ps(1.0f), _mm_sqrt_ps(x)));
    }
    static Vec max_magnitude(Vec a, Vec b, Vec c) {
        const Vec sign = _mm_set1_ps(-0.0f);
        return _mm_max_ps(_mm_andnot_ps(sign, a), _mm_max_ps(_mm_andnot_ps(sign, b), _mm_andnot_ps(sign, c)));
    }
    static Vec reciprocal_or_zero(Vec x) {
        return _mm_and_ps(_mm_cmpgt_ps(x, _mm_setzero_ps()), _mm_div_ps(_mm_set1_ps(1.0f), x));
    }
    static void store(float* p, Vec v) { _mm_storeu_ps(p, v); }
    static void store_rows(float* rows, Vec x, Vec y, Vec z) { store_four_rows(rows, x, y, z); }
};

void patch_sse41(const float points[kPatchPoints][4], const float* weights, int count, int stride, float* positions,
                 float* normals) {
    patch_pass<PatchSse41>(points, weights, count, stride, positions, normals);
}

}  // namespace loopsub::detail
