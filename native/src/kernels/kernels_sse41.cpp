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

// One quad of every smooth vertex and edge point of the ranges; Out is PackedQuads, PackedRows3 or QuadTarget. Rows
// of three (the last level's positions) go four points at a time (PackedRows3::store_four).
// A step of a tangent's sum (kernels_limit.h): the reference's multiply, then add.
constexpr auto multiply_add = [](__m128 w, __m128 d, __m128 sum) { return _mm_add_ps(sum, _mm_mul_ps(w, d)); };

// The unit normals t1 x t2 of four tangent pairs (x, y, z in a quad's first lanes), in double two at a time: the
// reference's arithmetic (limit_normals.cpp), zero where the tangents do not span a plane.
constexpr auto unit_normals = [](const __m128 t1[4], const __m128 t2[4], __m128 normal[4]) {
    __m128 a0 = t1[0], a1 = t1[1], a2 = t1[2], a3 = t1[3], b0 = t2[0], b1 = t2[1], b2 = t2[2], b3 = t2[3];
    _MM_TRANSPOSE4_PS(a0, a1, a2, a3);  // a0: the four x, a1: y, a2: z
    _MM_TRANSPOSE4_PS(b0, b1, b2, b3);
    __m128 n[3];
    for (int half = 0; half < 2; ++half) {  // vertices 0 and 1, then 2 and 3
        auto wide = [half](__m128 v) { return _mm_cvtps_pd(half == 0 ? v : _mm_movehl_ps(v, v)); };
        const __m128d ax = wide(a0), ay = wide(a1), az = wide(a2), bx = wide(b0), by = wide(b1), bz = wide(b2);
        const __m128d x = _mm_sub_pd(_mm_mul_pd(ay, bz), _mm_mul_pd(az, by));
        const __m128d y = _mm_sub_pd(_mm_mul_pd(az, bx), _mm_mul_pd(ax, bz));
        const __m128d z = _mm_sub_pd(_mm_mul_pd(ax, by), _mm_mul_pd(ay, bx));
        const __m128d length =
            _mm_sqrt_pd(_mm_add_pd(_mm_add_pd(_mm_mul_pd(x, x), _mm_mul_pd(y, y)), _mm_mul_pd(z, z)));
        const __m128d inverse =
            _mm_and_pd(_mm_cmpgt_pd(length, _mm_setzero_pd()), _mm_div_pd(_mm_set1_pd(1.0), length));
        const __m128 part[3] = {_mm_cvtpd_ps(_mm_mul_pd(x, inverse)), _mm_cvtpd_ps(_mm_mul_pd(y, inverse)),
                                _mm_cvtpd_ps(_mm_mul_pd(z, inverse))};
        for (int c = 0; c < 3; ++c) n[c] = half == 0 ? part[c] : _mm_movelh_ps(n[c], part[c]);
    }
    __m128 unused = _mm_setzero_ps();
    _MM_TRANSPOSE4_PS(n[0], n[1], n[2], unused);
    normal[0] = n[0], normal[1] = n[1], normal[2] = n[2], normal[3] = unused;
};

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
    grandchild_limit_pass(lt, in, out, normals, share, smooth_vertex, multiply_add, unit_normals, limit_sse41);
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
};

void patch_sse41(const float points[kPatchPoints][4], const float* weights, int count, int stride, float* positions,
                 float* normals) {
    patch_pass<PatchSse41>(points, weights, count, stride, positions, normals);
}

}  // namespace loopsub::detail
