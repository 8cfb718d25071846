// Where each point of a tessellation takes its position from: a vertex of its band's limit plan, a regular patch of
// the band's level under weights shared by every point at its place, or a stencil of the refined neighbourhood; and
// the blocks of weights of the triangles that are patches of the input.
#include "tessellate/tessellation_builder.h"

namespace loopsub::detail {

void TessellationBuilder::add_sample(int band, FacePoint at, int f) {
    const TessellationImpl::Band& b = d_.bands[std::size_t(band)];
    BandBuilder& bb = band_builders_[std::size_t(band)];
    int t = bb.face[std::size_t(f)], within = 0;  // the level's triangle, and its number among f's descendants
    for (int l = 0; l <= b.levels; ++l) {
        if (l == b.limit_levels) {  // a vertex here, or never one
            const int corner = at.T == 0 ? (at.S == 0      ? 0
                                            : at.S == at.D ? 1
                                                           : -1)
                                         : (at.S == 0 && at.T == at.D ? 2 : -1);
            if (corner >= 0) return add_vertex(band, t, corner);
        }
        if (l == b.levels) break;
        const int child = detail::descend(at);
        t = 4 * t + child, within = 4 * within + child;
    }
    if (!bb.patches) make_control(band);
    std::int32_t& patch = subface_patch_[std::size_t(within)];
    if (patch == kUnknown) patch = find_patch(bb, t), touched_.push_back(within);
    const std::uint8_t in_band = std::uint8_t(band);
    if (patch >= 0) {
        const auto [rotation, shape] = patch_shape_[std::size_t(patch)];
        d_.samples.push_back({Kind::Patch, in_band, patch, weight_set(rotation, shape, at)});
        return;
    }
    bb.local->weights(t, at, stencil_);
    d_.samples.push_back({Kind::Stencil, in_band, std::int32_t(d_.stencil_offsets.size() - 1), 0});
    for (std::size_t i = 0; i < stencil_.points.size(); ++i) {
        d_.stencil_points.push_back(stencil_.points[i]);
        const float w[3] = {float(stencil_.position[i]), float(stencil_.ds[i]), float(stencil_.dt[i])};
        d_.stencil_weights.insert(d_.stencil_weights.end(), w, w + 3);
    }
    d_.stencil_offsets.push_back(std::int64_t(d_.stencil_points.size()));
}

std::int32_t TessellationBuilder::block(const FacePattern& pattern, const Sides& sides, int part,
                                        std::pair<int, detail::PatchShape> shape) {
    const int begin = part == 0 ? 0 : detail::first_edge_point(sides.rates, part - 1);
    const int end = part == 0 ? 3 : part < 4 ? detail::first_edge_point(sides.rates, part) : int(pattern.points.size());
    if (begin == end) return -1;
    // The inner points depend on the inner rate, and on whether the rates differ below an inner rate of 3 (a
    // centre).
    const int rate = part == 0 ? 0 : part < 4 ? sides.rates[part - 1] : (end - begin == 1 ? -1 : sides.inner_rate());
    const BlockKey key{part, rate, shape.first, shape.second};
    const auto [found, added] = blocks_.try_emplace(key, std::int32_t(d_.blocks.size()));
    if (!added) return found->second;
    const int count = end - begin, stride = (count + 7) / 8 * 8;
    d_.blocks.push_back({count, stride, d_.block_weights.size()});
    d_.block_weights.resize(d_.block_weights.size() + std::size_t(3 * kPoints) * std::size_t(stride), 0.0f);
    float* weights = &d_.block_weights[d_.blocks.back().first];
    Patch patch;
    patch.rotation = shape.first, patch.shape = shape.second;
    for (int q = 0; q < count; ++q) {
        const detail::PatternPoint& at = pattern.points[std::size_t(begin + q)];
        detail::PatchWeights w;
        detail::patch_weights(patch, double(at.b1) / at.den, double(at.b2) / at.den, w);
        const double* kinds[3] = {w.position, w.ds, w.dt};
        for (int k = 0; k < 3; ++k)
            for (int i = 0; i < kPoints; ++i)
                weights[std::size_t(kPoints * k + i) * std::size_t(stride) + std::size_t(q)] = float(kinds[k][i]);
    }
    return found->second;
}

void TessellationBuilder::add_vertex(int band, int t, int corner) {
    const Plan& limit = *d_.bands[std::size_t(band)].limit;
    const std::size_t c = 3 * std::size_t(t) + std::size_t(corner);
    d_.samples.push_back(
        {Kind::Vertex, std::uint8_t(band), limit.output_triangles()[c], limit.corner_normal_indices()[c]});
}

std::int32_t TessellationBuilder::find_patch(const BandBuilder& bb, int t) {
    Patch patch;
    if (!bb.patches->find_patch(t, patch)) return -1;
    const std::int32_t number = std::int32_t(d_.patch_points.size() / detail::kBoxSplinePoints);
    for (std::int32_t p : patch.points) d_.patch_points.push_back(p);
    patch_shape_.push_back({patch.rotation, patch.shape});
    return number;
}

std::int32_t TessellationBuilder::weight_set(int rotation, detail::PatchShape shape, const FacePoint& at) {
    const WeightKey key{at.S, at.T, at.D, rotation, shape};
    const auto [found, added] = weight_sets_.try_emplace(key, std::int32_t(d_.patch_weights.size() / (3 * kPoints)));
    if (!added) return found->second;
    Patch patch;
    patch.rotation = rotation, patch.shape = shape;
    detail::PatchWeights w;
    detail::patch_weights(patch, double(at.S) / double(at.D), double(at.T) / double(at.D), w);
    for (const double* part : {w.position, w.ds, w.dt})
        for (int i = 0; i < kPoints; ++i) d_.patch_weights.push_back(float(part[i]));
    return found->second;
}

}  // namespace loopsub::detail
