// The scalar reference kernel: one output at a time, every channel, exactly the masks of stencils.h.
#include <algorithm>
#include <cmath>

#include "kernels/kernels.h"
#include "kernels/kernels_specials.h"
#include "kernels/limit_normals.h"

namespace loopsub::detail {

void refine_scalar(const LevelStencils& s, const StencilView& t, ChannelsView<const float> in, ChannelsView<float> out,
                   Range vertices, Range edges) {
    const std::size_t ie = in.element_stride, oe = out.element_stride;
    for (int c = 0; c < in.num_channels; ++c) {
        const float* p = in.data + c * in.channel_stride;
        float* q = out.data + c * out.channel_stride;
        for (int i = vertices.begin; i < vertices.end; ++i) {
            const int first = t.ring_first(i), valence = t.valence(i);
            float ring_sum = 0.0f;
            for (int k = first; k < first + valence; ++k) ring_sum += p[t.ring[k] * ie];
            q[i * oe] = s.smooth_self[valence] * p[i * ie] + s.smooth_ring[valence] * ring_sum;
        }
        float* edge_out = q + std::size_t(s.num_vertices) * oe;
        for (int e = edges.begin; e < edges.end; ++e) {
            edge_out[e * oe] = kSmoothEdgeEndWeight * (p[t.end(e, 0) * ie] + p[t.end(e, 1) * ie]) +
                               kSmoothEdgeWingWeight * (p[t.wing_c(e) * ie] + p[t.wing_d(e) * ie]);
        }
    }
    // The special masks over the smooth results, in the same arithmetic as the loop over channels above.
    apply_specials(s, t, in, out, vertices, edges);
}

void refine_fans_scalar(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out,
                        Range parent_edges) {
    // The reference reads the same points from the tables.
    const int nv = s.fan_first_midpoint;
    refine_scalar(s, stored_view(s), in, out, {nv + parent_edges.begin, nv + parent_edges.end},
                  {2 * parent_edges.begin, 2 * parent_edges.end});
}

void limit_scalar(const LimitTables& lt, const StencilView& view, ChannelsView<const float> in, ChannelsView<float> out,
                  float* normals, Range vertices) {
    refine_scalar(lt.positions, view, in, out, vertices, {0, 0});
    if (normals != nullptr) vertex_normals_reference(lt, view, in, normals, vertices);
}

void refine_interior_scalar(const LevelStencils& s, ChannelsView<const float> in, ChannelsView<float> out,
                            Range faces) {
    const LevelStencils::InteriorFaces& interior = *s.interior;
    const std::size_t ie = in.element_stride, oe = out.element_stride;
    for (int c = 0; c < in.num_channels; ++c) {
        const float* p = in.data + c * in.channel_stride;
        float* edge_out = out.data + c * out.channel_stride + (std::size_t(s.num_vertices) + interior.first_edge) * oe;
        for (int f = faces.begin; f < faces.end; ++f) {
            for (int k = 0; k < 3; ++k) {
                std::int32_t abcd[4];
                face_interior_edge(interior.parent_vertices, &interior.face_vertices[3 * std::size_t(f)],
                                   &interior.face_edges[3 * std::size_t(f)], k, abcd);
                edge_out[(3 * std::size_t(f) + k) * oe] = kSmoothEdgeEndWeight * (p[abcd[0] * ie] + p[abcd[1] * ie]) +
                                                          kSmoothEdgeWingWeight * (p[abcd[2] * ie] + p[abcd[3] * ie]);
            }
        }
    }
}

// The reference for kernels_patch.h: the same sums in the same order, a sample at a time.
void patch_scalar(const float points[kPatchPoints][4], const float* weights, int count, int stride, float* positions,
                  float* normals) {
    for (int s = 0; s < count; ++s) {
        float sum[3][3] = {};
        for (int i = 0; i < kPatchPoints; ++i)
            for (int k = 0; k < 3; ++k) {
                const float w = weights[std::size_t(kPatchPoints * k + i) * std::size_t(stride) + std::size_t(s)];
                for (int c = 0; c < 3; ++c) sum[k][c] = w * points[i][c] + sum[k][c];
            }
        float a[3], b[3];
        auto largest_inverse = [](const float* x) {
            const float m = std::max(std::fabs(x[0]), std::max(std::fabs(x[1]), std::fabs(x[2])));
            return m > 0.0f ? 1.0f / m : 0.0f;
        };
        const float a_unit = largest_inverse(sum[1]), b_unit = largest_inverse(sum[2]);
        for (int c = 0; c < 3; ++c) a[c] = sum[1][c] * a_unit, b[c] = sum[2][c] * b_unit;
        const float n[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
        const float length2 = n[0] * n[0] + (n[1] * n[1] + n[2] * n[2]);
        const float unit = length2 > 0.0f ? 1.0f / std::sqrt(length2) : 0.0f;
        for (int c = 0; c < 3; ++c)
            positions[3 * std::size_t(s) + std::size_t(c)] = sum[0][c],
                                           normals[3 * std::size_t(s) + std::size_t(c)] = n[c] * unit;
    }
}

}  // namespace loopsub::detail
