// A tessellation's frame: every point placed from the bands' plans (their limit points and normals, their control
// points under a patch's or a stencil's weights) or, in a triangle that is a patch of the input, by the patch kernel
// over its blocks of weights; and its face-varying layers' values.
#include <algorithm>
#include <cassert>
#include <cmath>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#include <limits>
#include <string>

#include "base/input_checks.h"
#include "base/parallel.h"
#include "tessellate/tessellation_data.h"

namespace loopsub {

namespace {

// The position, and the unit normal of the derivatives s x t (zero where they span no plane).
void finish_sums(const float* p, const float* s, const float* t, float position[3], float normal[3]) {
    const double n[3] = {double(s[1]) * t[2] - double(s[2]) * t[1], double(s[2]) * t[0] - double(s[0]) * t[2],
                         double(s[0]) * t[1] - double(s[1]) * t[0]};
    const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const double inverse = length > 0.0 ? 1.0 / length : 0.0;
    for (int c = 0; c < 3; ++c) position[c] = p[c], normal[c] = float(n[c] * inverse);
}

using Kind = TessellationImpl::Kind;

// Sums of weighted control points (3 floats each, read four at a time: the buffer has a float to spare at its end):
// the position and its two derivatives, then the position and unit normal they give. SSE2, every x86-64's, with its
// scalar twin elsewhere.
#if defined(__SSE2__)
class PointSums {
public:
    void add(const float* x, float wp, float ws, float wt) {
        const __m128 v = _mm_loadu_ps(x);
        p_ = _mm_add_ps(p_, _mm_mul_ps(_mm_set1_ps(wp), v));
        s_ = _mm_add_ps(s_, _mm_mul_ps(_mm_set1_ps(ws), v));
        t_ = _mm_add_ps(t_, _mm_mul_ps(_mm_set1_ps(wt), v));
    }
    void finish(float position[3], float normal[3]) const {
        alignas(16) float p[4], s[4], t[4];
        _mm_store_ps(p, p_), _mm_store_ps(s, s_), _mm_store_ps(t, t_);
        finish_sums(p, s, t, position, normal);
    }

private:
    __m128 p_ = _mm_setzero_ps(), s_ = _mm_setzero_ps(), t_ = _mm_setzero_ps();
};
#else
class PointSums {
public:
    void add(const float* x, float wp, float ws, float wt) {
        for (int c = 0; c < 3; ++c) p_[c] += wp * x[c], s_[c] += ws * x[c], t_[c] += wt * x[c];
    }
    void finish(float position[3], float normal[3]) const { finish_sums(p_, s_, t_, position, normal); }

private:
    float p_[3] = {0, 0, 0}, s_[3] = {0, 0, 0}, t_[3] = {0, 0, 0};
};
#endif

// A point's three floats. std::copy_n of three compiles to a call of memmove, which cost more than the copy once per
// sample (docs/benchmark.md, "The tessellation's frame").
void copy_point(const float* from, float* to) { to[0] = from[0], to[1] = from[1], to[2] = from[2]; }

constexpr int kPoints = detail::kPatchPoints;

// A patch sums 12 weighted points, its derivatives' weights up to about 6 in all: inputs below the float maximum over
// 64 keep every sum finite (the bound a plan puts as max / (summed terms + 1)).
constexpr int kPositionSummedTerms = 63;
constexpr float kLargestPosition = std::numeric_limits<float>::max() / float(kPositionSummedTerms + 1);

// Each band's plans on its vertices' positions: the limit points and normals, and the control points.
void evaluate_bands(const TessellationImpl& d, const float* positions) {
    for (const TessellationImpl::Band& b : d.bands) {
        b.positions.resize(3 * b.vertices.size());
        for (std::size_t v = 0; v < b.vertices.size(); ++v)
            copy_point(positions + 3 * std::size_t(b.vertices[v]), &b.positions[3 * v]);
        const ChannelsView<const float> in = interleaved(b.positions.data(), 3);
        b.limit_points.resize(3 * std::size_t(b.limit->num_output_vertices()));
        b.limit_normals.resize(3 * std::size_t(b.limit->num_limit_normals()));
        b.limit->evaluate(in, interleaved(b.limit_points.data(), 3), Plan::LimitNormals{b.limit_normals.data()});
        if (b.control) {
            b.control_points.resize(3 * std::size_t(b.control->num_output_vertices()) + 1);
            b.control->evaluate(in, interleaved(b.control_points.data(), 3));
        }
    }
}

// An input triangle that is a patch: its 12 points for the patch kernel, over its block of weights; the positions of
// the points it places copied out, but for its inner points: its own, one after the other, written in place.
void place_patch_face(const TessellationImpl& d, std::size_t f, const float* positions, float* points, float* normals,
                      std::vector<float>& scratch) {
    const std::int32_t* patch = &d.input_patch_points[std::size_t(d.face_patch[f]) * kPoints];
    alignas(16) float x[kPoints][4] = {};  // a phantom's point is zero, with zero weights
    for (int i = 0; i < kPoints; ++i)
        if (patch[i] >= 0) copy_point(positions + 3 * std::size_t(patch[i]), x[i]);
    std::size_t sample = std::size_t(d.face_first_sample[f]);
    for (int part = 0; part < TessellationImpl::kParts; ++part) {
        const std::int32_t b = d.face_blocks[TessellationImpl::kParts * f + std::size_t(part)];
        if (b < 0) continue;
        const TessellationImpl::Block& block = d.blocks[std::size_t(b)];
        float* part_normals = normals ? normals + 3 * sample : scratch.data() + 3 * std::size_t(block.count);
        if (part == TessellationImpl::kInnerPart) {
            const std::int32_t first_point = d.sample_point[sample];
            for (int q = 0; q < block.count; ++q) assert(d.sample_point[sample + std::size_t(q)] == first_point + q);
            d.patch_kernel(x, &d.block_weights[block.first], block.count, block.stride,
                           points + 3 * std::size_t(first_point), part_normals);
            sample += std::size_t(block.count);
            continue;
        }
        d.patch_kernel(x, &d.block_weights[block.first], block.count, block.stride, scratch.data(), part_normals);
        for (int q = 0; q < block.count; ++q, ++sample)
            if (const std::int32_t point = d.sample_point[sample]; point >= 0)
                copy_point(&scratch[3 * std::size_t(q)], points + 3 * std::size_t(point));
    }
}

// A face point through its band's plans: a limit point and normal, or a patch's or a stencil's sums over the control
// points; its point written where it places one.
void place_sample(const TessellationImpl& d, std::size_t s, float* points, float* normals) {
    const TessellationImpl::Sample& sample = d.samples[s];
    const TessellationImpl::Band& band = d.bands[sample.band];
    const float* x = band.control_points.data();
    float p[3], n[3];
    if (sample.kind == Kind::Vertex) {
        copy_point(&band.limit_points[3 * std::size_t(sample.a)], p);
        copy_point(&band.limit_normals[3 * std::size_t(sample.b)], n);
    } else {
        PointSums sums;
        if (sample.kind == Kind::Patch) {
            const std::int32_t* patch = &d.patch_points[std::size_t(sample.a) * kPoints];
            const float* w = &d.patch_weights[std::size_t(sample.b) * 3 * kPoints];
            for (int i = 0; i < kPoints; ++i)
                if (patch[i] >= 0) sums.add(x + 3 * std::size_t(patch[i]), w[i], w[kPoints + i], w[2 * kPoints + i]);
        } else {
            const std::size_t first = std::size_t(d.stencil_offsets[std::size_t(sample.a)]),
                              last = std::size_t(d.stencil_offsets[std::size_t(sample.a) + 1]);
            for (std::size_t i = first; i < last; ++i) {
                const float* w = &d.stencil_weights[3 * i];
                sums.add(x + 3 * std::size_t(d.stencil_points[i]), w[0], w[1], w[2]);
            }
        }
        sums.finish(p, n);
    }
    if (const std::int32_t point = d.sample_point[s]; point >= 0) copy_point(p, points + 3 * std::size_t(point));
    if (normals) copy_point(n, normals + 3 * s);
}

}  // namespace

void Tessellation::evaluate_face_varying(int layer, const float* values, int channels, float* out) const {
    const TessellationImpl& d = *impl_;
    if (layer < 0 || layer >= int(d.layers.size()))
        throw InputError("tessellation: face-varying layer " + std::to_string(layer) + " is not in 0.." +
                         std::to_string(int(d.layers.size()) - 1));
    if (channels < 1) throw InputError("tessellation: at least one face-varying channel is needed");
    const TessellationImpl::Layer& l = d.layers[std::size_t(layer)];
    const std::size_t c = std::size_t(channels);
    // Finite; where the layer's surface places them as positions, within its bound too (else its own check would
    // name a vertex of the layer's mesh, not the caller's value).
    detail::check_values(interleaved(values, channels), l.num_values, InputProblem::Element::FaceVaryingValue, layer,
                         l.surface ? kLargestPosition : 0.0f, kPositionSummedTerms,
                         detail::ThrowFirst{"tessellation: "});
    const std::size_t num_face_points = d.samples.size();
    if (!l.surface) {
        for (std::size_t f = 0; f < num_face_points; ++f) {
            const std::int32_t* v = &l.corner_values[3 * std::size_t(d.face_point_parent[f])];
            const float u = d.parameters[2 * f], w = d.parameters[2 * f + 1];
            for (std::size_t j = 0; j < c; ++j) {
                const float a = values[std::size_t(v[0]) * c + j], b = values[std::size_t(v[1]) * c + j],
                            e = values[std::size_t(v[2]) * c + j];
                out[f * c + j] = a + u * (b - a) + w * (e - a);
            }
        }
        return;
    }
    // The layer's surface places three channels at a time, as positions.
    std::vector<float> positions(3 * l.base_values.size()), points(3 * std::size_t(l.surface->num_points()));
    for (std::size_t first = 0; first < c; first += 3) {
        const std::size_t count = std::min<std::size_t>(3, c - first);
        for (std::size_t x = 0; x < l.base_values.size(); ++x)
            for (std::size_t j = 0; j < 3; ++j)
                positions[3 * x + j] = j < count ? values[std::size_t(l.base_values[x]) * c + first + j] : 0.0f;
        l.surface->evaluate(positions.data(), points.data(), nullptr);
        for (std::size_t f = 0; f < num_face_points; ++f)
            for (std::size_t j = 0; j < count; ++j)
                out[f * c + first + j] = points[3 * std::size_t(l.face_point_point[f]) + j];
    }
}

void Tessellation::evaluate(const float* positions, float* points, float* normals) const {
    const TessellationImpl& d = *impl_;
    const std::size_t num_faces = d.face_patch.size();
    detail::check_values(interleaved(positions, 3), d.num_input_vertices, InputProblem::Element::Vertex, -1,
                         kLargestPosition, kPositionSummedTerms, detail::ThrowFirst{"tessellation: "});
    evaluate_bands(d, positions);
    for (const std::int32_t v : d.lone_vertices)
        copy_point(positions + 3 * std::size_t(v), points + 3 * std::size_t(v));
    // Each part's scratch takes the largest block once: resized block by block, it was zeroed again for every face.
    std::size_t largest_block = 0;
    for (const TessellationImpl::Block& block : d.blocks)
        largest_block = std::max(largest_block, std::size_t(block.count));
    detail::run_levels(d.threads, 1, [&](int, int part, int parts) {
        const auto [first, last] = detail::part_of(num_faces, part, parts);
        std::vector<float> scratch(6 * largest_block);
        for (std::size_t f = first; f < last; ++f) {
            if (d.face_patch[f] >= 0) {
                place_patch_face(d, f, positions, points, normals, scratch);
                continue;
            }
            for (std::size_t s = std::size_t(d.face_first_sample[f]); s < std::size_t(d.face_first_sample[f + 1]); ++s)
                place_sample(d, s, points, normals);
        }
    });
}

}  // namespace loopsub
