// The scalar reference kernel: one output at a time, every channel, exactly the masks of stencils.h.
#include <algorithm>

#include "kernels.h"

namespace loopsub::detail {

namespace {

// The specials whose target lies in [begin, end), from a list sorted by target.
template <typename Special, typename Target>
std::pair<const Special*, const Special*> specials_in(const std::vector<Special>& specials, Range range, Target target) {
    auto lo = std::lower_bound(specials.begin(), specials.end(), range.begin,
                               [&](const Special& s, int v) { return target(s) < v; });
    auto hi = std::lower_bound(lo, specials.end(), range.end, [&](const Special& s, int v) { return target(s) < v; });
    return {specials.data() + (lo - specials.begin()), specials.data() + (hi - specials.begin())};
}

}  // namespace

void refine_scalar(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out, Range vertices,
                   Range edges) {
    const std::size_t ie = in.element_stride, oe = out.element_stride;
    const auto [sv_begin, sv_end] = specials_in(s.special_vertices, vertices, [](const SpecialVertex& v) { return v.vertex; });
    const auto [se_begin, se_end] = specials_in(s.special_edges, edges, [](const SpecialEdge& e) { return e.edge; });

    for (int c = 0; c < in.num_channels; ++c) {
        const float* p = in.data + c * in.channel_stride;
        float* q = out.data + c * out.channel_stride;

        for (int i = vertices.begin; i < vertices.end; ++i) {
            const int first = s.ring_offsets[i], last = s.ring_offsets[i + 1];
            float ring_sum = 0.0f;
            for (int k = first; k < last; ++k) ring_sum += p[s.ring[k] * ie];
            const int valence = last - first;
            q[i * oe] = s.smooth_self[valence] * p[i * ie] + s.smooth_ring[valence] * ring_sum;
        }
        for (const SpecialVertex* v = sv_begin; v != sv_end; ++v) {
            float ring_sum = 0.0f;
            for (int k = s.ring_offsets[v->vertex]; k < s.ring_offsets[v->vertex + 1]; ++k) ring_sum += p[s.ring[k] * ie];
            q[v->vertex * oe] = v->w_self * p[v->vertex * ie] + v->w_ring * ring_sum +
                                v->w_crease_a * p[v->crease_a * ie] + v->w_crease_b * p[v->crease_b * ie];
        }

        float* edge_out = q + std::size_t(s.num_vertices) * oe;
        for (int e = edges.begin; e < edges.end; ++e) {
            edge_out[e * oe] = kSmoothEdgeEndWeight * (p[s.edge_ends[2 * e] * ie] + p[s.edge_ends[2 * e + 1] * ie]) +
                               kSmoothEdgeWingWeight * (p[s.edge_c[e] * ie] + p[s.edge_d[e] * ie]);
        }
        for (const SpecialEdge* e = se_begin; e != se_end; ++e) {
            edge_out[e->edge * oe] = e->wa * p[s.edge_ends[2 * e->edge] * ie] + e->wb * p[s.edge_ends[2 * e->edge + 1] * ie] +
                                     e->wcd * (p[s.edge_c[e->edge] * ie] + p[s.edge_d[e->edge] * ie]);
        }
    }
}

}  // namespace loopsub::detail
