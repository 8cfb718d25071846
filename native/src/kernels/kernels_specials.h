// The special-mask pass shared by the SIMD kernels: creases, corners, boundaries, semi-sharp blends, {5,3} edges.
//
// Specials are few (a crease curve doubles its length per level while the surface quadruples its area), so every
// kernel runs the smooth masks over its whole range and then overwrites these outputs one at a time, in the scalar
// arithmetic. Only the outputs of the caller's ranges are written (threads share lists).
// Internal linkage, as in kernels_quads.h: each instruction set's translation unit keeps its own copy.
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>

#include "kernels/kernels.h"

namespace loopsub::detail {
namespace {

// The specials whose target lies in [begin, end), from a list sorted by target.
template <typename Special, typename Target>
std::pair<const Special*, const Special*> specials_in_range(const std::vector<Special>& specials, Range range,
                                                            Target target) {
    const auto before = [&](const Special& s, int t) { return target(s) < t; };
    const auto lo = std::lower_bound(specials.begin(), specials.end(), range.begin, before);
    const auto hi = std::lower_bound(lo, specials.end(), range.end, before);
    return {specials.data() + (lo - specials.begin()), specials.data() + (hi - specials.begin())};
}

// Overwrites the special vertex points of `vertices` and special edge points of `edges`, every channel.
inline void apply_specials(const LevelStencils& s, const StencilView& t, ChannelsView<const float> in,
                           ChannelsView<float> out, Range vertices, Range edges) {
    const std::size_t ie = in.element_stride, oe = out.element_stride;
    const auto [sv_begin, sv_end] =
        specials_in_range(s.special_vertices, vertices, [](const SpecialVertex& v) { return v.vertex; });
    const auto [se_begin, se_end] =
        specials_in_range(s.special_edges, edges, [](const SpecialEdge& e) { return e.edge; });

    for (const SpecialVertex* v = sv_begin; v != sv_end; ++v) {
        const int first = t.ring_first(v->vertex), last = first + t.valence(v->vertex);
        for (int c = 0; c < in.num_channels; ++c) {
            const float* p = in.data + c * in.channel_stride;
            float ring_sum = 0.0f;
            for (int k = first; k < last; ++k) ring_sum += p[t.ring[k] * ie];
            out.data[c * out.channel_stride + v->vertex * oe] = v->w_self * p[v->vertex * ie] + v->w_ring * ring_sum +
                                                                v->w_crease_a * p[v->crease_a * ie] +
                                                                v->w_crease_b * p[v->crease_b * ie];
        }
    }
    const auto [rv_begin, rv_end] =
        specials_in_range(s.ring_weighted_vertices, vertices, [](const RingWeightedVertex& v) { return v.vertex; });
    for (const RingWeightedVertex* v = rv_begin; v != rv_end; ++v) {
        const int first = t.ring_first(v->vertex), valence = t.valence(v->vertex);
        const float* w = s.ring_weights.data() + v->first;
        for (int c = 0; c < in.num_channels; ++c) {
            const float* p = in.data + c * in.channel_stride;
            float sum = v->w_self * p[v->vertex * ie];
            for (int k = 0; k < valence; ++k) sum += w[k] * p[t.ring[first + k] * ie];
            out.data[c * out.channel_stride + v->vertex * oe] = sum;
        }
    }
    for (const SpecialEdge* e = se_begin; e != se_end; ++e) {
        const std::size_t a = t.end(e->edge, 0) * ie, b = t.end(e->edge, 1) * ie;
        const std::size_t c = t.wing_c(e->edge) * ie, d = t.wing_d(e->edge) * ie;
        const std::size_t target = (std::size_t(s.num_vertices) + e->edge) * oe;
        for (int ch = 0; ch < in.num_channels; ++ch) {
            const float* p = in.data + ch * in.channel_stride;
            out.data[ch * out.channel_stride + target] = e->wa * p[a] + e->wb * p[b] + e->wcd * (p[c] + p[d]);
        }
    }
}

}  // namespace
}  // namespace loopsub::detail
