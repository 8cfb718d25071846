// SSE4.1 kernel: the masks of the scalar reference (kernels_scalar.cpp), four channels at a time.
//
// SIMD runs across channels: with the input in quads (kernels_quads.h) one 16-byte load fetches a neighbour's
// x, y, z and a fourth channel, and each vertex or edge point is one short loop of loads and adds in the
// reference's order (SSE4.1 has no FMA: the results equal the reference bit for bit). Other input layouts run the
// reference itself: SSE4.1 has no gather, and vectors built across outputs from planar data (a load and an insert
// per lane and channel) measured slower than the scalar code.
// Special vertices and edges (creases, corners, boundaries) are recomputed afterwards (kernels_specials.h).
#include <smmintrin.h>

#include "kernels.h"
#include "kernels_quads.h"
#include "kernels_specials.h"

namespace loopsub::detail {

namespace {

// One quad of every smooth vertex and edge point of the ranges; Out is PackedQuads, PackedRows3 or QuadTarget.
template <std::size_t Step, typename Out>
void smooth_quad(const Tables& t, const QuadSource<Step> in, const Out out, Range vertices, Range edges) {
    for (int i = vertices.begin; i < vertices.end; ++i) {
        const int first = t.ring_first(i), valence = t.valence(i), last = first + valence;
        __m128 ring_sum = _mm_setzero_ps();
        for (int k = first; k < last; ++k) ring_sum = _mm_add_ps(ring_sum, _mm_loadu_ps(in.at(t.ring[k])));
        out.store(i, _mm_add_ps(_mm_mul_ps(_mm_set1_ps(t.smooth_self[valence]), _mm_loadu_ps(in.at(i))),
                                _mm_mul_ps(_mm_set1_ps(t.smooth_ring[valence]), ring_sum)));
    }
    const __m128 end_weight = _mm_set1_ps(kSmoothEdgeEndWeight);
    const __m128 wing_weight = _mm_set1_ps(kSmoothEdgeWingWeight);
    for (int e = edges.begin; e < edges.end; ++e) {
        const __m128 ends = _mm_add_ps(_mm_loadu_ps(in.at(t.end(e, 0))), _mm_loadu_ps(in.at(t.end(e, 1))));
        const __m128 wings = _mm_add_ps(_mm_loadu_ps(in.at(t.wing_c(e))), _mm_loadu_ps(in.at(t.wing_d(e))));
        out.store(t.first_edge_point + e, _mm_add_ps(_mm_mul_ps(end_weight, ends), _mm_mul_ps(wing_weight, wings)));
    }
}

}  // namespace

void refine_sse41(const LevelStencils& s, const StencilView& view, ChannelsView<const float> in, ChannelsView<float> out,
                  Range vertices, Range edges) {
    if (!reads_as_quads(in)) return refine_scalar(s, view, in, out, vertices, edges);
    for_each_quad(s, view, in, out, [&](const Tables& tables, auto source, auto target) {
        smooth_quad(tables, source, target, vertices, edges);
    });
    apply_specials(s, view, in, out, vertices, edges);
}

}  // namespace loopsub::detail
