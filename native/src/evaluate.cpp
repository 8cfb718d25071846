// The per-frame work: checks of the values, then the kernels over the plan's stencil tables, level by level, in
// parallel parts; and the linear refinement of face-varying values.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common.h"
#include "kernels.h"
#include "parallel.h"
#include "plan_data.h"
#include "validation.h"

namespace loopsub {

using detail::fail;
using detail::ms_since;
using detail::run_levels;
using Clock = detail::Clock;

void Plan::evaluate(ChannelsView<const float> in, ChannelsView<float> out) {
    PlanImpl& p = *impl_;
    const auto start = Clock::now();
    const int channels = in.num_channels;
    if (channels != out.num_channels)
        fail("evaluate: input has " + std::to_string(channels) + " channels but output has " + std::to_string(out.num_channels));
    if (channels < 1) fail("evaluate: at least one channel is needed, got " + std::to_string(channels));
    if ((in.data == nullptr && p.num_input_vertices > 0) || (out.data == nullptr && num_output_vertices() > 0))
        fail("evaluate: missing (null) data");
    auto input = [&](int v, int c) { return in.data[c * in.channel_stride + std::size_t(v) * in.element_stride]; };
    // Every mask's weights are non-negative and sum to one, so a refined value never exceeds the largest input; only
    // the sums inside a kernel can overflow, and the bound keeps them finite.
    const float largest = p.options.levels > 0 ? std::numeric_limits<float>::max() / float(p.max_summed_terms + 1)
                                               : std::numeric_limits<float>::max();
    detail::validate_vertex_values(in, p.num_input_vertices, largest, p.max_summed_terms);

    const int levels = p.options.levels;
    if (p.num_input_vertices == 0) {  // nothing to refine (and the output may be a null pointer)
        p.evaluate_ms = ms_since(start);
        return;
    }
    // The limit is one more pass, over the last level's vertices only.
    const int passes = levels + (p.limit ? 1 : 0);
    auto pass_stencils = [&p, levels](int pass) -> const detail::LevelStencils& {
        return pass < levels ? p.stencils[pass] : p.limit->positions;
    };
    if (passes == 0) {
        for (int v = 0; v < p.num_input_vertices; ++v)
            for (int c = 0; c < channels; ++c) out.data[c * out.channel_stride + std::size_t(v) * out.element_stride] = input(v, c);
        p.evaluate_ms = ms_since(start);
        return;
    }

    // Levels are refined in quads: a vertex's channels side by side, padded with zeros to a multiple of four, so
    // that a kernel fetches every channel of a neighbour with one aligned 16-byte load (kernels_quads.h); with
    // gathers from planar arrays each channel of each neighbour is a load of its own, measured 1.7x slower
    // (docs/benchmark.md). The padding refines like a channel (zeros stay zeros); the last pass is written
    // straight into `out`. Pass l reads scratch[(l + 1) % 2] and writes scratch[l % 2].
    const std::size_t padded = (std::size_t(channels) + 3) / 4 * 4;
    std::size_t needed[2] = {0, 0};
    needed[1] = std::size_t(p.num_input_vertices);
    for (int l = 0; l + 1 < passes; ++l) needed[l % 2] = std::max(needed[l % 2], std::size_t(p.level_num_vertices[l + 1]));
    for (int b = 0; b < 2; ++b) p.scratch[b].resize(needed[b] * padded);
    auto quads = [&](int buffer) { return ChannelsView<float>{p.scratch[buffer].data(), int(padded), 1, padded}; };
    const ChannelsView<float> first = quads(1);
    for (int v = 0; v < p.num_input_vertices; ++v)
        for (std::size_t c = 0; c < padded; ++c) first.data[v * padded + c] = c < std::size_t(channels) ? input(v, int(c)) : 0.0f;

    std::vector<ChannelsView<const float>> sources(passes);
    std::vector<ChannelsView<float>> targets(passes);
    for (int l = 0; l < passes; ++l) {
        sources[l] = quads((l + 1) % 2);
        targets[l] = l + 1 < passes ? quads(l % 2) : out;
    }
    // The padding only serves the SIMD loads: the scalar kernel leaves it alone, and the last pass drops it.
    for (int l = 0; l < passes; ++l) {
        if (p.kernel == Kernel::Scalar) sources[l].num_channels = targets[l].num_channels = channels;
    }
    sources[passes - 1].num_channels = channels;

    const detail::RefineFn refine = detail::refine_function(p.kernel);
    run_levels(std::max(1, p.options.threads), passes, [&](int pass, int part, int parts) {
        const detail::LevelStencils& s = pass_stencils(pass);
        // Small levels are not worth splitting.
        if (s.num_vertices + s.num_edges < 4096) {
            if (part == 0) refine(s, sources[pass], targets[pass], {0, s.num_vertices}, {0, s.num_edges});
            return;
        }
        auto split = [parts](int n, int i) { return int(std::int64_t(n) * i / parts); };
        refine(s, sources[pass], targets[pass], {split(s.num_vertices, part), split(s.num_vertices, part + 1)},
               {split(s.num_edges, part), split(s.num_edges, part + 1)});
    });
    p.evaluate_ms = ms_since(start);
}

void Plan::evaluate(ChannelsView<const float> in, ChannelsView<float> out, float* corner_normals) {
    PlanImpl& p = *impl_;
    if (!p.limit) fail("evaluate: normals are the limit surface's; build the plan with Options::limit_surface");
    if (in.num_channels < 3) fail("evaluate: normals need positions in the first three channels, got " + std::to_string(in.num_channels) + " channels");
    if (corner_normals == nullptr && num_output_triangles() > 0) fail("evaluate: missing (null) normals");
    evaluate(in, out);
    const auto start = Clock::now();
    if (p.num_input_vertices == 0) return;
    // The last level's refined points: the limit pass's source, still in scratch (or the input, with no levels).
    const int levels = p.options.levels;
    const std::size_t padded = (std::size_t(in.num_channels) + 3) / 4 * 4;
    const ChannelsView<const float> last =
        levels == 0 ? in : ChannelsView<const float>{p.scratch[(levels + 1) % 2].data(), in.num_channels, 1, padded};
    p.limit_normals(last, corner_normals);
    p.evaluate_ms += ms_since(start);
}

void Plan::evaluate_face_varying(const float* in, float* out, int num_channels) const {
    const PlanImpl& p = *impl_;
    if (num_channels < 1) fail("evaluate_face_varying: at least one channel is needed, got " + std::to_string(num_channels));
    const std::size_t corner = std::size_t(num_channels), face = 3 * corner;
    if ((in == nullptr && p.num_input_triangles > 0) || (out == nullptr && num_output_triangles() > 0))
        fail("evaluate_face_varying: missing (null) data");
    detail::validate_face_varying_values(in, std::size_t(p.num_input_triangles), num_channels);
    std::vector<float> current(in, in + face * p.num_input_triangles), next;
    for (int l = 0; l < p.options.levels; ++l) {
        const std::size_t faces = current.size() / face;
        next.resize(4 * current.size());
        for (std::size_t f = 0; f < faces; ++f) {
            const float* u = &current[f * face];
            float* child = &next[4 * f * face];
            for (std::size_t c = 0; c < corner; ++c) {
                const float u0 = u[c], u1 = u[corner + c], u2 = u[2 * corner + c];
                // Halves first: the same value as (a + b) / 2 without its overflow for values past half the float range.
                const float m0 = 0.5f * u0 + 0.5f * u1, m1 = 0.5f * u1 + 0.5f * u2, m2 = 0.5f * u2 + 0.5f * u0;
                // Children (v0, m0, m2), (v1, m1, m0), (v2, m2, m1), (m0, m1, m2), as in refine_topology.
                const float values[12] = {u0, m0, m2, u1, m1, m0, u2, m2, m1, m0, m1, m2};
                for (int k = 0; k < 12; ++k) child[k * corner + c] = values[k];
            }
        }
        current.swap(next);
    }
    std::copy(current.begin(), current.end(), out);
}

}  // namespace loopsub
