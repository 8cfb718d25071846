// The build of a Tessellation in order (build), and each input triangle's points numbered, its samples and its
// triangles written from its pattern (add_face).
#include "tessellate/tessellation_builder.h"

#include <algorithm>
#include <string>

namespace loopsub::detail {

void TessellationBuilder::build(const TessellationRates& rates, const std::shared_ptr<const KeptInput>& kept) {
    // The input first: its limit plan of no levels checks the mesh and the options before anything reads them (a
    // kept one checked the same).
    d_.input = kept && kept->made_for(mesh_, options_) ? kept : std::make_shared<const KeptInput>(mesh_, options_);
    const KeptInput& input = *d_.input;
    options_.limit_surface = true;  // the bands' limit plans (their levels set each)
    // The input's plan decided which triangles have a surface; the bands' plans refine every triangle they hold (all
    // shape the surface), under the same rules: Boundary::None's are EdgesOnly's but for those faces.
    if (options_.boundary == Boundary::None) options_.boundary = Boundary::EdgesOnly;
    const EdgeRates edges = edges_with_rates(input, mesh_.num_vertices, rates);
    d_.num_input_vertices = mesh_.num_vertices;
    std::vector<Sides> sides(std::size_t(mesh_.num_triangles));
    std::vector<std::int64_t> face_first(std::size_t(mesh_.num_triangles));
    const ResultCounts counts = sides_and_bands(input, edges, sides, face_first);
    const std::uint64_t bytes = check_budget(input, counts);
    refinement_bytes_ = {options_.memory_limit_bytes, bytes, bytes};
    for (std::size_t b = 0; b < d_.bands.size(); ++b) {
        options_.levels = d_.bands[b].limit_levels;
        d_.bands[b].limit = std::make_unique<Plan>(band_builders_[b].view, options_);
    }
    d_.num_points = counts.points;
    placed_.assign(std::size_t(counts.points), 0);
    d_.samples.reserve(std::size_t(counts.samples)), d_.sample_point.reserve(std::size_t(counts.samples));
    d_.triangles.reserve(3 * std::size_t(counts.triangles)),
        d_.corner_face_points.reserve(3 * std::size_t(counts.triangles));
    d_.parent_triangles.reserve(std::size_t(counts.triangles));
    d_.parameters.reserve(2 * std::size_t(counts.samples));
    subface_patch_.assign(std::size_t(1) << 2 * d_.levels, kUnknown);
    for (int f = 0; f < mesh_.num_triangles; ++f) {
        if (input.surface(f)) {
            add_face(f, sides[std::size_t(f)], face_first[std::size_t(f)]);
            continue;
        }
        d_.face_first_sample.push_back(std::int32_t(d_.samples.size()));  // no samples, no blocks
        d_.face_blocks.insert(d_.face_blocks.end(), TessellationImpl::kParts, -1);
    }
    d_.face_first_sample.push_back(std::int32_t(d_.samples.size()));
    for (std::int32_t v = 0; v < mesh_.num_vertices; ++v)  // of no triangle with a surface: stays where it is
        if (!placed_[std::size_t(v)]) d_.lone_vertices.push_back(v);
    d_.estimated_bytes = refinement_bytes_.peak;
}

// Each input triangle's sides and the number of its first inner point; a triangle that is a patch of the input takes
// its patch, every other joins the band of the levels its rates need.
TessellationBuilder::ResultCounts TessellationBuilder::sides_and_bands(const KeptInput& input, const EdgeRates& edges,
                                                                       std::vector<Sides>& sides,
                                                                       std::vector<std::int64_t>& face_first) {
    ResultCounts counts{edges.end_point, 0, 0};
    d_.face_patch.assign(std::size_t(mesh_.num_triangles), -1);
    face_band_.assign(std::size_t(mesh_.num_triangles), -1);
    for (int f = 0; f < mesh_.num_triangles; ++f) {
        if (!input.surface(f)) continue;  // no points, samples or triangles
        Sides& s = sides[std::size_t(f)];
        for (int k = 0; k < 3; ++k) {
            const std::int32_t a = mesh_.triangles[3 * f + k], b = mesh_.triangles[3 * f + (k + 1) % 3];
            const std::size_t e = std::size_t(input.edges.corner_edges[3 * std::size_t(f) + std::size_t(k)]);
            s.rates[k] = edges.rates[e], s.first_point[k] = edges.first_point[e];
            s.along[k] = a < b;
        }
        face_first[std::size_t(f)] = counts.points;
        const std::int64_t inner = detail::num_inner_points(s.rates, s.inner_rate());
        counts.points += inner;
        counts.samples += detail::first_edge_point(s.rates, 3) + inner;
        counts.triangles += detail::num_pattern_triangles(s.rates, s.inner_rate());
        if (const std::int32_t found = input.face_patch[std::size_t(f)]; found >= 0) {
            const Patch& patch = input.patch_list[std::size_t(found)];
            d_.face_patch[std::size_t(f)] = std::int32_t(input_shapes_.size());
            d_.input_patch_points.insert(d_.input_patch_points.end(), patch.points,
                                         patch.points + detail::kBoxSplinePoints);
            input_shapes_.push_back({patch.rotation, patch.shape});
            continue;
        }
        join_band(f, s);
    }
    return counts;
}

// Its band: the levels its rates need (2^L at least its largest). The points at vertices of a level are those i / r
// along an edge of rate r, or of the inner lattice, whose denominator, reduced, is a power of two: vertices of the
// level of the largest power of two in any rate, which the band's limit plan need go no deeper than.
void TessellationBuilder::join_band(int f, const Sides& s) {
    int levels = 0;
    while ((1 << levels) < s.inner_rate()) ++levels;
    const auto [band, added] = band_of_levels_.try_emplace(levels, int(d_.bands.size()));
    if (added) d_.bands.emplace_back().levels = levels, band_builders_.emplace_back();
    face_band_[std::size_t(f)] = band->second;
    TessellationImpl::Band& b = d_.bands[std::size_t(band->second)];
    for (int rate : {s.rates[0], s.rates[1], s.rates[2], s.inner_rate()})
        b.limit_levels = std::max(b.limit_levels, two_adic(rate));
    d_.levels = std::max(d_.levels, levels);
}

// What the result holds: per face point its sample, point, parameters and a normal; per triangle its corners, their
// face points and its parent; per point its position. Then each band's two plans (limit and control points,
// Plan::estimate_bytes of its submesh, made here): one budget for all, checked before any of them is made.
std::uint64_t TessellationBuilder::check_budget(const KeptInput& input, const ResultCounts& counts) {
    std::uint64_t bytes =
        std::uint64_t(counts.samples) * 40 + std::uint64_t(counts.triangles) * 28 + std::uint64_t(counts.points) * 16;
    const std::uint64_t result_bytes = bytes;
    for (std::size_t b = 0; b < d_.bands.size(); ++b) {
        make_submesh(*input.patches, int(b));
        const MeshView& sub = band_builders_[b].view;
        const auto sub_edges = std::int64_t(detail::sorted_edge_keys(sub.triangles, sub.num_triangles).size());
        for (int levels : {d_.bands[b].limit_levels, d_.bands[b].levels})
            bytes += Plan::estimate_bytes(sub.num_vertices, sub.num_triangles, levels, 3, sub_edges);
    }
    if (bytes > options_.memory_limit_bytes)
        throw MemoryLimitError("tessellation: " + std::to_string(counts.triangles) + " triangles would need about " +
                                   describe_bytes(bytes) + " (the result " + describe_bytes(result_bytes) +
                                   ", the plans of the triangles that are no patch the rest), more than the "
                                   "limit of " +
                                   describe_bytes(options_.memory_limit_bytes),
                               bytes);
    if (counts.points > std::int64_t(INT32_MAX) || counts.samples > std::int64_t(INT32_MAX) ||
        3 * counts.triangles > std::int64_t(INT32_MAX))
        throw MemoryLimitError("tessellation: more than 2^31 points", bytes);
    return bytes;
}

void TessellationBuilder::add_face(int f, const Sides& s, std::int64_t face_first) {
    // A pattern depends on the rates alone: made once for each triple of them (at one rate, once in all), with its
    // points' parameters.
    const auto [cached, added] = patterns_.try_emplace({s.rates[0], s.rates[1], s.rates[2]});
    if (added) {
        detail::tessellate_triangle(s.rates, s.inner_rate(), cached->second.pattern);
        for (const detail::PatternPoint& at : cached->second.pattern.points)
            cached->second.parameters.insert(cached->second.parameters.end(),
                                             {float(double(at.b1) / at.den), float(double(at.b2) / at.den)});
    }
    const FacePattern& pattern = cached->second.pattern;
    const int first_inner = detail::first_edge_point(s.rates, 3);
    std::vector<std::int32_t>& number = numbers_;
    number.resize(pattern.points.size());
    int p = 0;
    for (; p < 3; ++p) number[std::size_t(p)] = mesh_.triangles[3 * f + p];
    for (int k = 0; k < 3; ++k)
        for (int i = 1; i < s.rates[k]; ++i, ++p)
            number[std::size_t(p)] = std::int32_t(s.first_point[k] + (s.along[k] ? i : s.rates[k] - i) - 1);
    for (; p < int(pattern.points.size()); ++p)  // TessellationImpl::kInnerPart
        number[std::size_t(p)] = std::int32_t(face_first + p - first_inner);

    const int first_sample = int(d_.samples.size());
    d_.face_first_sample.push_back(first_sample);
    for (std::int32_t within : touched_) subface_patch_[std::size_t(within)] = kUnknown;
    touched_.clear();
    const std::int32_t input_patch = d_.face_patch[std::size_t(f)];
    for (const std::int32_t point : number) {
        d_.sample_point.push_back(placed_[std::size_t(point)] ? -1 : point);
        placed_[std::size_t(point)] = 1;
    }
    d_.parameters.insert(d_.parameters.end(), cached->second.parameters.begin(), cached->second.parameters.end());
    if (input_patch >= 0) d_.samples.insert(d_.samples.end(), pattern.points.size(), {Kind::InputPatch, 0, -1, -1});
    else
        for (const detail::PatternPoint& at : pattern.points)
            add_sample(face_band_[std::size_t(f)], FacePoint{at.b1, at.b2, at.den}, f);
    for (int part = 0; part < TessellationImpl::kParts; ++part)
        d_.face_blocks.push_back(input_patch >= 0 ? block(pattern, s, part, input_shapes_[std::size_t(input_patch)])
                                                  : -1);
    const std::size_t corners = d_.triangles.size();
    d_.triangles.resize(corners + pattern.triangles.size());
    d_.corner_face_points.resize(corners + pattern.triangles.size());
    for (std::size_t c = 0; c < pattern.triangles.size(); ++c) {
        const std::int32_t p = pattern.triangles[c];
        d_.triangles[corners + c] = number[std::size_t(p)];
        d_.corner_face_points[corners + c] = first_sample + p;
    }
    d_.parent_triangles.insert(d_.parent_triangles.end(), pattern.triangles.size() / 3, f);
}

}  // namespace loopsub::detail
