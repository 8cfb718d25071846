// The per-frame work: checks of the values, then the kernels over the plan's stencil tables, level by level, in
// parallel parts, for vertex data and face-varying layers alike; the limit normals; and the linear refinement of
// per-corner face-varying values.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "base/common.h"
#include "kernels/kernels.h"
#include "kernels/limit_normals.h"
#include "base/parallel.h"
#include "plan/plan_data.h"
#include "plan/validation.h"

namespace loopsub {

using detail::fail;
using detail::ms_since;
using detail::run_levels;
using Clock = detail::Clock;

namespace {

// A level of a frame is cut into this many pieces per thread, which the threads take in turn (Team::run): where
// another process holds a core up now and then, a held-up thread's share goes to the other (docs/benchmark.md,
// "Threads"). The plan's passes keep fixed halves, as pieces made them no faster, but where two kinds of work share a
// step (fill_tables_from_parent).
constexpr int kPiecesPerThread = 4;

// Channels a run of passes refines at once (run_passes): one quad.
constexpr int kQuadChannels = 4;

// Floats per element in the scratch levels (see run_quad_passes).
std::size_t scratch_stride(int channels) { return channels == 3 ? 3 : kQuadChannels; }

// run_passes for at most kQuadChannels channels: pass i reads counts[i] elements and writes counts[i + 1]; the first
// reads load(element, channel), the last writes `out`. With `limit` (the plan's limit tables, then the last of
// `passes`), the last pass is the limit kernel's, which also writes the vertex normals where `normals` is set, and a
// step after it the sides' (Plan::LimitNormals' layout).
//
// Passes run on quads: an element's channels side by side, padded with zeros to four, so that a kernel fetches every
// channel of a neighbour with one 16-byte load (kernels_quads.h); with gathers from planar arrays each channel of each
// neighbour is a load of its own (docs/benchmark.md, "Why the kernels evaluate in quads"). The padding refines like a
// channel (zeros stay zeros). Three channels (positions) are not padded: a 16-byte load then also reads the next
// element's first channel, which goes unused, and a level takes a quarter less memory; the scratch ends with a quad of
// zeros for the last element's load. Pass i reads scratch[(i + 1) % 2] and writes scratch[i % 2].
template <typename Load>
void run_quad_passes(PlanImpl& p, const std::vector<const detail::LevelStencils*>& passes,
                     const std::vector<int>& counts, int channels, Load load, ChannelsView<float> out,
                     const detail::LimitTables* limit, float* normals) {
    const int n = int(passes.size());
    if (n == 0) {
        for (int v = 0; v < counts[0]; ++v)
            for (int c = 0; c < channels; ++c)
                out.data[c * out.channel_stride + std::size_t(v) * out.element_stride] = load(v, c);
        return;
    }
    const std::size_t padded = scratch_stride(channels);
    std::size_t needed[2] = {0, std::size_t(counts[0])};
    for (int i = 0; i + 1 < n; ++i) needed[i % 2] = std::max(needed[i % 2], std::size_t(counts[i + 1]));
    for (int b = 0; b < 2; ++b) {
        p.frame.scratch[b].resize(needed[b] * padded + 4);
        std::fill(p.frame.scratch[b].end() - 4, p.frame.scratch[b].end(), 0.0f);
    }
    auto quads = [&](int buffer) {
        return ChannelsView<float>{p.frame.scratch[buffer].data(), int(padded), 1, padded};
    };
    float* first = p.frame.scratch[1].data();
    for (int v = 0; v < counts[0]; ++v)
        for (std::size_t c = 0; c < padded; ++c)
            first[v * padded + c] = c < std::size_t(channels) ? load(v, int(c)) : 0.0f;

    std::vector<ChannelsView<const float>>& sources = p.frame.sources;
    std::vector<ChannelsView<float>>& targets = p.frame.targets;
    sources.resize(std::size_t(n));
    targets.resize(std::size_t(n));
    for (int i = 0; i < n; ++i) {
        sources[i] = quads((i + 1) % 2);
        targets[i] = i + 1 < n ? quads(i % 2) : out;
        // The padding only serves the SIMD loads: the scalar kernel leaves it alone, and the last pass drops it.
        if (p.kernel == Kernel::Scalar || i + 1 == n) sources[i].num_channels = channels;
        if (p.kernel == Kernel::Scalar) targets[i].num_channels = channels;
    }
    const detail::Kernels kernels = detail::kernel_functions(p.kernel);
    const bool sides = limit != nullptr && normals != nullptr && !limit->sides.empty();
    run_levels(
        std::max(1, p.options.threads), n + int(sides),
        [&](int pass, int part, int parts) {
            if (pass == n) {  // the sides' normals, from the last level's points
                const auto [begin, end] = detail::part_of(int(limit->sides.size()), part, parts);
                return detail::side_normals(*limit, sources[n - 1], normals, {begin, end});
            }
            const detail::LevelStencils& s = *passes[pass];
            // Small levels are not worth splitting.
            if (s.num_vertices + s.num_edges < 4096) {
                if (part != 0) return;
                part = 0, parts = 1;
            }
            if (limit != nullptr && pass == n - 1)
                return detail::limit_part(kernels, *limit, sources[pass], targets[pass], normals, part, parts);
            detail::refine_part(kernels, s, sources[pass], targets[pass], part, parts);
        },
        kPiecesPerThread);
}

// Runs stencil passes (refinement levels, then the limit) over data of `channels` channels, a quad of channels at a
// time (run_quad_passes), the normals (where `normals` is set) with the first, the positions'. Each quad's levels are
// then as dense as four channels make them: with all channels side by side, each neighbour a kernel loads would be a
// cache line of its own past four channels, and sixteen channels took 15 times four's time (docs/benchmark.md).
template <typename Load>
void run_passes(PlanImpl& p, const std::vector<const detail::LevelStencils*>& passes, const std::vector<int>& counts,
                int channels, Load load, ChannelsView<float> out, const detail::LimitTables* limit = nullptr,
                float* normals = nullptr) {
    for (int first = 0; first < channels; first += kQuadChannels) {
        ChannelsView<float> quad = out;
        quad.data += std::size_t(first) * out.channel_stride;
        quad.num_channels = std::min(kQuadChannels, channels - first);
        run_quad_passes(
            p, passes, counts, quad.num_channels, [&load, first](int v, int c) { return load(v, first + c); }, quad,
            limit, first == 0 ? normals : nullptr);
    }
}

// Every mask's weights are non-negative and sum to one, so a refined value never exceeds the largest input; only the
// sums inside a kernel can overflow, and this bound keeps them finite.
float largest_refinable(const PlanImpl& p) {
    return p.options.levels > 0 || p.limit ? std::numeric_limits<float>::max() / float(p.max_summed_terms + 1)
                                           : std::numeric_limits<float>::max();
}

}  // namespace

namespace {

// Plan::evaluate's work, with the limit normals where `normals` is set (checked by the caller).
void evaluate_vertices(PlanImpl& p, ChannelsView<const float> in, ChannelsView<float> out, float* normals) {
    const auto start = Clock::now();
    const int channels = in.num_channels;
    if (channels != out.num_channels)
        fail("evaluate: input has " + std::to_string(channels) + " channels but output has " +
             std::to_string(out.num_channels));
    if (channels < 1) fail("evaluate: at least one channel is needed, got " + std::to_string(channels));
    const int num_output_vertices = p.level_num_vertices.back();
    if ((in.data == nullptr && p.num_input_vertices > 0) || (out.data == nullptr && num_output_vertices > 0))
        fail("evaluate: missing (null) data");
    detail::validate_vertex_values(in, p.num_input_vertices, largest_refinable(p), p.max_summed_terms);
    if (p.num_input_vertices > 0) {  // otherwise nothing to refine (and the output may be a null pointer)
        std::vector<const detail::LevelStencils*>& passes = p.frame.passes;
        passes.clear();
        for (const detail::LevelStencils& s : p.stencils) passes.push_back(&s);
        if (p.limit) passes.push_back(&p.limit->positions);
        std::vector<int>& counts = p.frame.counts;
        counts.assign(p.level_num_vertices.begin(), p.level_num_vertices.end());
        if (p.limit) counts.push_back(counts.back());
        run_passes(
            p, passes, counts, channels,
            [&in](int v, int c) { return in.data[c * in.channel_stride + std::size_t(v) * in.element_stride]; }, out,
            p.limit.get(), normals);
    }
    p.frame.evaluate_ms = ms_since(start);
}

}  // namespace

void Plan::evaluate(ChannelsView<const float> in, ChannelsView<float> out) {
    evaluate_vertices(*impl_, in, out, nullptr);
}

int Plan::num_face_varying_layers() const { return int(impl_->face_varying.size()); }

namespace {
const detail::FaceVaryingPlan& layer_plan(const PlanImpl& p, int layer) {
    if (layer < 0 || layer >= int(p.face_varying.size()))
        throw std::out_of_range("face-varying layer " + std::to_string(layer) + " is not in 0.." +
                                std::to_string(int(p.face_varying.size()) - 1));
    return p.face_varying[layer];
}
}  // namespace

const std::int32_t* Plan::output_face_varying_indices(int layer) const {
    return layer_plan(*impl_, layer).output_corner_values.data();
}
int Plan::num_output_face_varying_values(int layer) const { return layer_plan(*impl_, layer).counts.back(); }

Plan::FaceVaryingBase Plan::face_varying_base(int layer) const {
    const detail::FaceVaryingPlan& plan = layer_plan(*impl_, layer);
    FaceVaryingBase base;
    base.corner_values.assign(plan.base_corner_values.begin(), plan.base_corner_values.end());
    base.values.assign(plan.base_values.begin(), plan.base_values.end());
    for (std::uint8_t c : plan.base_classes) base.classes.push_back(FaceVaryingValueClass(c));
    return base;
}

void Plan::evaluate_face_varying(int layer, ChannelsView<const float> in, ChannelsView<float> out) {
    PlanImpl& p = *impl_;
    const detail::FaceVaryingPlan& plan = layer_plan(p, layer);
    const int channels = in.num_channels;
    if (channels != out.num_channels)
        fail("evaluate_face_varying: input has " + std::to_string(channels) + " channels but output has " +
             std::to_string(out.num_channels));
    if (channels < 1) fail("evaluate_face_varying: at least one channel is needed, got " + std::to_string(channels));
    if ((in.data == nullptr && plan.num_input_values > 0) || (out.data == nullptr && plan.counts.back() > 0))
        fail("evaluate_face_varying: missing (null) data");
    detail::validate_vertex_values(in, plan.num_input_values, largest_refinable(p), p.max_summed_terms,
                                   InputProblem::Element::FaceVaryingValue, layer);
    if (plan.counts[0] == 0) return;
    std::vector<const detail::LevelStencils*>& passes = p.frame.passes;
    passes.clear();
    for (const detail::LevelStencils& s : plan.passes) passes.push_back(&s);
    run_passes(
        p, passes, plan.counts, channels,
        [&in, &plan](int x, int c) {
            return in.data[c * in.channel_stride + std::size_t(plan.base_values[x]) * in.element_stride];
        },
        out);
}

namespace {

void check_normals_input(const PlanImpl& p, ChannelsView<const float> in) {
    if (!p.limit) fail("evaluate: normals are the limit surface's; build the plan with Options::limit_surface");
    if (in.num_channels < 3)
        fail("evaluate: normals need positions in the first three channels, got " + std::to_string(in.num_channels) +
             " channels");
}

}  // namespace

void Plan::evaluate(ChannelsView<const float> in, ChannelsView<float> out, LimitNormals normals) {
    PlanImpl& p = *impl_;
    check_normals_input(p, in);
    if (normals.normals == nullptr && num_limit_normals() > 0) fail("evaluate: missing (null) normals");
    evaluate_vertices(p, in, out, normals.normals);
}

void Plan::evaluate(ChannelsView<const float> in, ChannelsView<float> out, float* corner_normals) {
    PlanImpl& p = *impl_;
    check_normals_input(p, in);
    if (corner_normals == nullptr && num_output_triangles() > 0) fail("evaluate: missing (null) normals");
    detail::LargeVector<float>& normals = p.frame.normals;
    normals.resize(3 * std::size_t(num_limit_normals()));
    evaluate(in, out, LimitNormals{normals.data()});
    const auto start = Clock::now();
    if (p.num_input_vertices == 0) return;
    // Each corner its vertex's normal, then the corners on sides their side's, in the same part of the corner range.
    const std::vector<std::pair<Index, Index>>& corner_sides = p.limit->corner_sides;
    run_levels(std::max(1, p.options.threads), 1, [&](int, int part, int parts) {
        const auto [begin, end] = detail::part_of(p.output_triangles.size(), part, parts);
        for (std::size_t c = begin; c < end; ++c) {
            const float* n = &normals[3 * std::size_t(p.output_triangles[c])];
            corner_normals[3 * c] = n[0], corner_normals[3 * c + 1] = n[1], corner_normals[3 * c + 2] = n[2];
        }
        for (const auto& [corner, row] : corner_sides) {  // a few per sharp edge, in vertex order: each part reads all
            const std::size_t c = std::size_t(corner);
            if (c < begin || c >= end) continue;
            const float* n = &normals[3 * std::size_t(row)];
            corner_normals[3 * c] = n[0], corner_normals[3 * c + 1] = n[1], corner_normals[3 * c + 2] = n[2];
        }
    });
    p.frame.evaluate_ms += ms_since(start);
}

void Plan::evaluate_face_varying(const float* in, float* out, int num_channels) const {
    const PlanImpl& p = *impl_;
    if (num_channels < 1)
        fail("evaluate_face_varying: at least one channel is needed, got " + std::to_string(num_channels));
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
                // Halves first: the same value as (a + b) / 2 without its overflow for values past half the float
                // range.
                const float m0 = 0.5f * u0 + 0.5f * u1, m1 = 0.5f * u1 + 0.5f * u2, m2 = 0.5f * u2 + 0.5f * u0;
                // Children (v0, m0, m2), (v1, m1, m0), (v2, m2, m1), (m0, m1, m2), as in refine_topology.
                const float values[12] = {u0, m0, m2, u1, m1, m0, u2, m2, m1, m0, m1, m2};
                for (int k = 0; k < 12; ++k) child[k * corner + c] = values[k];
            }
        }
        current.swap(next);
    }
    if (p.holes.empty()) {
        std::copy(current.begin(), current.end(), out);
        return;
    }
    for (std::size_t t = 0; t < p.kept_triangles.size(); ++t)
        std::copy_n(current.begin() + std::size_t(p.kept_triangles[t]) * face, face, out + t * face);
}

}  // namespace loopsub
