// Which face-varying values follow the seam rules, and how (rules/face_varying_rules.h): their tags at the base level
// (classify_base) and how they change as semi-sharp features decay (release_values); the builder gathers each vertex's
// and value's facts and asks the rules.
#include <algorithm>
#include <vector>

#include "base/parallel.h"
#include "plan/face_varying.h"
#include "plan/face_varying_parts.h"
#include "rules/face_varying_rules.h"

namespace loopsub::detail {

// Vtr::FVarLevel::completeTopologyFromFaceValues: which values follow the seam rules, and how (face_varying_rules.h);
// the vertices in parts, each writing its own values' tags.
void FaceVaryingBuilder::classify_base(const LevelState& base) {
    const Mode mode = options_.face_varying;
    tags_.assign(values_.num_vertices, Tag{});
    if (mode == Mode::All) {
        for (Tag& tag : tags_) tag.mismatch = true;
        return;
    }
    const Topology& t = base.topology;
    const std::vector<std::uint8_t> vertex_non_manifold =
        non_manifold_vertices(t, non_manifold_edges(t), options_.threads);
    const std::vector<std::uint8_t> value_non_manifold =
        non_manifold_vertices(values_, non_manifold_edges(values_), options_.threads);
    TransientVector<Index> offsets, at_vertex;
    group_by_vertex(vertex_of_.data(), vertex_of_.size(), t.num_vertices, offsets, at_vertex,
                    parts_for(vertex_of_.size()));
    const int parts = parts_for(std::size_t(values_.num_vertices));
    run_levels(parts, 1, [&](int, int part, int) {
        Walk walk;
        std::vector<FaceVaryingSpan> spans;
        std::vector<Tag> tags;
        const auto [v0, v1] = part_of(t.num_vertices, part, parts);
        for (int v = v0; v < v1; ++v) {
            const int n = offsets[v + 1] - offsets[v];
            if (n == 0) continue;
            const Index* values = at_vertex.data() + offsets[v];
            FaceVaryingVertex vertex = seam_vertex(t, v, n, vertex_non_manifold[v] != 0);
            if (!face_varying_mismatched(mode, options_.boundary, vertex)) continue;
            vertex.sharpness = base.vertex_sharpness(v);  // a search among the features: only where it is read
            spans.assign(n, FaceVaryingSpan{});
            if (!vertex.non_manifold)  // else every value stays, whatever its span
                for (int i = 0; i < n; ++i)
                    spans[i] = span_of(values[i], base, value_non_manifold[values[i]] != 0, walk);
            tags.resize(n);
            face_varying_base_tags(mode, vertex, spans.data(), tags.data());
            for (int i = 0; i < n; ++i) tags_[values[i]] = tags[i];
        }
    });
}

FaceVaryingVertex FaceVaryingBuilder::seam_vertex(const Topology& t, Index v, int values, bool non_manifold) const {
    bool boundary = false, seam = false;
    int face_corners = 0;
    for (Index k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k) {
        const Index e = t.vertex_edges[k];
        boundary |= t.edge_face_count(e) == 1;
        seam |= split_[e] != 0;
        face_corners += t.edge_face_count(e);
    }
    return {values, seam, boundary, boundary && face_corners == 2, non_manifold, 0.0f};
}

FaceVaryingSpan FaceVaryingBuilder::span_of(Index x, const LevelState& base, bool disjoint, Walk& walk) const {
    FaceVaryingSpan span;
    for (Index e : edges_at(x, walk)) span.faces += values_.edge_face_count(e);
    span.faces /= 2;  // each face of the span has two of x's edges
    inner_edges(x, walk.inner, walk);
    for (Index e : walk.inner) {
        const float sharpness = base.edge_sharpness(e);
        span.infinite += is_infinite(sharpness);
        span.semi += is_semi_sharp(sharpness);
    }
    span.disjoint = disjoint;
    return span;
}

// Vtr::FVarRefinement::reclassifySemisharpValues at vertices [v0, v1) whose values are mismatched.
void FaceVaryingBuilder::release_values(const LevelState& level, const LevelState& child,
                                        const VertexNeighbourhood& vertex_level, const TransientVector<Index>& offsets,
                                        const TransientVector<Index>& at_vertex, Index v0, Index v1,
                                        TransientVector<Tag>& child_tags, Walk& walk) const {
    const Mode mode = options_.face_varying;
    if (mode == Mode::All) return;
    auto child_sharpness_at = [&](Index e, Index v) { return child.edge_sharpness(vertex_level.child_edge_at(e, v)); };
    for (Index v = v0; v < v1; ++v) {
        const int n = offsets[v + 1] - offsets[v];
        const Index* values = at_vertex.data() + offsets[v];
        if (n == 0 || !tags_[values[0]].mismatch) continue;
        std::vector<Index>& around = walk.around;
        around.clear();
        for (int i = 0; i < n; ++i)
            for (Index e : edges_at(values[i], walk)) around.push_back(edge_of_[e]);
        const bool parent_semi =
            is_semi_sharp(level.vertex_sharpness(v)) ||
            std::any_of(around.begin(), around.end(), [&](Index e) { return is_semi_sharp(level.edge_sharpness(e)); });
        if (!face_varying_may_release(parent_semi, child.vertex_sharpness(v))) continue;
        const bool child_semi_edges =
            std::any_of(around.begin(), around.end(), [&](Index e) { return is_semi_sharp(child_sharpness_at(e, v)); });
        walk.value_tags.clear();
        for (int i = 0; i < n; ++i) walk.value_tags.push_back(&child_tags[values[i]]);
        release_held_values(mode, walk.value_tags.data(), n, child_semi_edges, [&](int i) {
            inner_edges(values[i], walk.inner, walk);
            return std::any_of(walk.inner.begin(), walk.inner.end(),
                               [&](Index e) { return is_semi_sharp(child_sharpness_at(e, v)); });
        });
    }
}

}  // namespace loopsub::detail
