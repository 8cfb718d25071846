// The limit pass of a face-varying layer: where each value of the last level goes (its vertex's limit, its seam's, or
// where it is), and where a value held by semi-sharp features that outlast the last level goes once they are spent.
#include <algorithm>
#include <vector>

#include "base/parallel.h"
#include "plan/face_varying.h"
#include "plan/face_varying_parts.h"
#include "rules/face_varying_rules.h"

namespace loopsub::detail {

void FaceVaryingBuilder::plan_held_limits(const LevelState& last, const RuleSet& rules, LevelStencils& s) const {
    const Mode mode = options_.face_varying;
    if (mode == Mode::All) return;
    std::vector<Index> edges, inner;
    Walk walk;
    TransientVector<Index> offsets, at_vertex;
    group_by_vertex(vertex_of_.data(), vertex_of_.size(), last.topology.num_vertices, offsets, at_vertex,
                    parts_for(vertex_of_.size()));
    std::vector<std::vector<int>> inner_slots;
    std::vector<float> sharpness, child_sharpness, parent_inner, child_inner;
    std::vector<Tag> tags, child_tags;
    std::vector<Tag*> value_tags;
    struct Held {
        Index value, ends[2];
        double refinement[3][3];  // (value, end a, end b) down to where it follows the seam, or for good
        bool released;
    };
    std::vector<Held> held;
    for (int v = 0; v < last.topology.num_vertices; ++v) {
        const int n = offsets[v + 1] - offsets[v];
        const Index* values = at_vertex.data() + offsets[v];
        if (!std::any_of(values, values + n, [&](Index x) { return tags_[x].mismatch && tags_[x].semi_sharp; }))
            continue;
        // The vertex's edges (every one lies in some value's span) and each value's inner edges among them.
        edges.clear();
        for (int i = 0; i < n; ++i)
            for (Index e : edges_at(values[i], walk)) edges.push_back(edge_of_[e]);
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        inner_slots.assign(n, {});
        for (int i = 0; i < n; ++i) {
            inner_edges(values[i], inner, walk);
            for (Index e : inner)
                inner_slots[i].push_back(int(std::lower_bound(edges.begin(), edges.end(), e) - edges.begin()));
        }
        sharpness.clear();
        for (Index e : edges) sharpness.push_back(last.edge_sharpness(e));
        float vertex_sharpness = last.vertex_sharpness(v);
        tags.assign(n, Tag{});
        for (int i = 0; i < n; ++i) tags[i] = tags_[values[i]];
        const std::size_t first_held = held.size();
        for (int i = 0; i < n; ++i) {
            Held h{values[i], {-1, -1}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, false};
            if (tags[i].semi_sharp && seam_ends(values[i], h.ends, walk)) held.push_back(h);
        }
        // Level after level as plan_level goes, until every held value follows its seam or nothing decays any more.
        auto is_semi_slot = [](const std::vector<float>& of, const std::vector<int>& slots) {
            return std::any_of(slots.begin(), slots.end(), [&](int k) { return is_semi_sharp(of[k]); });
        };
        auto all_released = [&] {
            return std::all_of(held.begin() + first_held, held.end(), [](const Held& h) { return h.released; });
        };
        while (!all_released() &&
               (is_semi_sharp(vertex_sharpness) || std::any_of(sharpness.begin(), sharpness.end(), is_semi_sharp))) {
            const float child_vertex = rules.child_vertex_sharpness(vertex_sharpness);
            child_sharpness.resize(sharpness.size());
            for (std::size_t k = 0; k < sharpness.size(); ++k)
                child_sharpness[k] = rules.child_edge_sharpness(sharpness[k], sharpness.data(), int(sharpness.size()));
            child_tags = tags;
            if (!is_sharp(child_vertex)) {
                value_tags.clear();
                for (Tag& tag : child_tags) value_tags.push_back(&tag);
                release_held_values(mode, value_tags.data(), n,
                                    std::any_of(child_sharpness.begin(), child_sharpness.end(), is_semi_sharp),
                                    [&](int i) { return is_semi_slot(child_sharpness, inner_slots[i]); });
            }
            for (std::size_t h = first_held; h < held.size(); ++h) {
                Held& value = held[h];
                if (value.released) continue;
                const int i = int(std::find(values, values + n, value.value) - values);
                VertexMask mask = corner_vertex_mask();
                if (child_tags[i].crease) {
                    mask = crease_vertex_mask();
                    // Blended with the hold by what decayed in its span, or its sibling's (plan_level's weight).
                    const int span = tags[i].dep_sharp && n == 2 ? 1 - i : i;
                    parent_inner.clear();
                    child_inner.clear();
                    for (int k : inner_slots[span])
                        parent_inner.push_back(sharpness[k]), child_inner.push_back(child_sharpness[k]);
                    const float w =
                        transition_weight(options_.crease_method, vertex_sharpness, child_vertex, parent_inner.data(),
                                          child_inner.data(), int(parent_inner.size()));
                    if (tags[i].semi_sharp) mask = blend(corner_vertex_mask(), w, mask);
                    value.released = true;
                }
                // The seam's midpoints are its next ends.
                const EdgeMask seam = crease_edge_mask();
                const double step[3][3] = {
                    {mask.self, mask.crease, mask.crease}, {seam.a, seam.b, 0.0}, {seam.a, 0.0, seam.b}};
                double product[3][3];
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c)
                        product[r][c] = step[r][0] * value.refinement[0][c] + step[r][1] * value.refinement[1][c] +
                                        step[r][2] * value.refinement[2][c];
                std::copy(&product[0][0], &product[0][0] + 9, &value.refinement[0][0]);
            }
            tags.swap(child_tags);
            sharpness.swap(child_sharpness);
            vertex_sharpness = child_vertex;
        }
    }
    // A released value goes to its seam's limit, one held for good stays.
    for (const Held& h : held) {
        const LimitMask limit = h.released ? crease_limit_mask() : corner_limit_mask();
        const double r[3] = {limit.self, limit.end_a, limit.end_b};
        double pulled[3];
        for (int c = 0; c < 3; ++c)
            pulled[c] = r[0] * h.refinement[0][c] + r[1] * h.refinement[1][c] + r[2] * h.refinement[2][c];
        s.special_vertices.push_back(
            {h.value, h.ends[0], h.ends[1], float(pulled[0]), 0.0f, float(pulled[1]), float(pulled[2])});
    }
    std::sort(s.special_vertices.begin(), s.special_vertices.end(),
              [](const SpecialVertex& a, const SpecialVertex& b) { return a.vertex < b.vertex; });
}

void FaceVaryingBuilder::plan_limit(const LimitTables& limit, const LevelState& last, const RuleSet& rules) {
    const LevelStencils& vertex_limit = limit.positions;
    const int nx = values_.num_vertices;
    LevelStencils& s = plan_.passes.emplace_back();
    s.num_vertices = nx;
    s.num_edges = 0;
    set_smooth_masks(s, values_.max_valence, smooth_limit_mask);
    // Values held by semi-sharp features that outlast the last level (plan_held_limits) first.
    plan_held_limits(last, rules, s);
    const std::size_t held = s.special_vertices.size();
    SpecialsByTarget<SpecialVertex> special_vertex(vertex_limit.special_vertices, vertex_limit.num_vertices,
                                                   [](const SpecialVertex& sv) { return sv.vertex; });
    SpecialsByTarget<RingWeightedVertex> ring_weighted(vertex_limit.ring_weighted_vertices, vertex_limit.num_vertices,
                                                       [](const RingWeightedVertex& rv) { return rv.vertex; });
    // In parts of the values, as plan_level: the vertex plan's masks as tables, then each part's values.
    const int parts = parts_for(std::size_t(nx));
    std::vector<PartOutput> outputs(static_cast<std::size_t>(parts));
    run_levels(parts, 2, [&](int step, int part, int) {
        if (step == 0) {
            const auto [v0, v1] = part_of(vertex_limit.num_vertices, part, parts);
            special_vertex.mark(v0, v1);
            ring_weighted.mark(v0, v1);
            return;
        }
        const auto [x0, x1] = part_of(nx, part, parts);
        plan_limit_points(limit, special_vertex, ring_weighted, s.special_vertices.data(), held, x0, x1,
                          outputs[std::size_t(part)]);
    });
    std::vector<std::size_t> weights_before(outputs.size() + 1, 0);
    for (std::size_t k = 0; k < outputs.size(); ++k)
        weights_before[k + 1] = weights_before[k] + outputs[k].ring_weights.size();
    for (std::size_t k = 0; k < outputs.size(); ++k)  // part-local places in the ring weights, made the joined list's
        for (RingWeightedVertex& rv : outputs[k].ring_weighted) rv.first += Index(weights_before[k]);
    std::vector<SpecialVertex> computed;
    join_in_parts(
        outputs, [](const PartOutput& out) -> const std::vector<SpecialVertex>& { return out.vertices; }, computed);
    join_in_parts(
        outputs, [](const PartOutput& out) -> const std::vector<RingWeightedVertex>& { return out.ring_weighted; },
        s.ring_weighted_vertices);
    join_in_parts(
        outputs, [](const PartOutput& out) -> const std::vector<float>& { return out.ring_weights; }, s.ring_weights);
    if (held == 0) {
        s.special_vertices = std::move(computed);
    } else {
        s.special_vertices.insert(s.special_vertices.end(), computed.begin(), computed.end());
        std::inplace_merge(s.special_vertices.begin(), s.special_vertices.begin() + std::ptrdiff_t(held),
                           s.special_vertices.end(),
                           [](const SpecialVertex& a, const SpecialVertex& b) { return a.vertex < b.vertex; });
    }
    const int copy_parts = parts_for(values_.vertex_vertices.size());
    s.ring_offsets = copy_in_parts(values_.vertex_edge_offsets, copy_parts);
    s.ring = copy_in_parts(values_.vertex_vertices, copy_parts);
    plan_.counts.push_back(nx);
}

void FaceVaryingBuilder::plan_limit_points(const LimitTables& limit,
                                           const SpecialsByTarget<SpecialVertex>& special_vertex,
                                           const SpecialsByTarget<RingWeightedVertex>& ring_weighted,
                                           const SpecialVertex* held, std::size_t num_held, Index x0, Index x1,
                                           PartOutput& out) const {
    const Mode mode = options_.face_varying;
    // Linear everywhere has no limit to go to; seam corners stay; seams go to their B-spline's limit; values with
    // no seam at their vertex go where the vertex goes (Far::PrimvarRefiner::LimitFaceVarying).
    const LimitMask crease = crease_limit_mask();
    const SpecialVertex* next_held =
        std::lower_bound(held, held + num_held, x0, [](const SpecialVertex& h, Index x) { return h.vertex < x; });
    Walk walk;
    for (Index x = x0; x < x1; ++x) {
        const Tag& tag = tags_[x];
        Index ends[2];
        if (next_held != held + num_held && next_held->vertex == x) {
            ++next_held;
        } else if (mode == Mode::All || (tag.mismatch && (!tag.crease || !seam_ends(x, ends, walk)))) {
            out.vertices.push_back(staying_value(x));
        } else if (tag.mismatch) {
            out.vertices.push_back(
                {x, ends[0], ends[1], float(crease.self), 0.0f, float(crease.end_a), float(crease.end_b)});
        } else if (const SpecialVertex* m = special_vertex[std::size_t(vertex_of_[x])]) {
            out.vertices.push_back(on_layer(x, *m, walk));
        } else if (const RingWeightedVertex* m = ring_weighted[std::size_t(vertex_of_[x])]) {
            // Without a seam at the vertex, the value's ring is the vertex's, value for neighbour, in its own order.
            Index buffer[6];
            const LimitRing ring = limit_ring(limit, m->vertex, buffer);
            out.ring_weighted.push_back({x, Index(out.ring_weights.size()), m->w_self});
            for (Index k = values_.vertex_edge_offsets[x]; k < values_.vertex_edge_offsets[x + 1]; ++k) {
                const Index neighbour = vertex_of_[values_.vertex_vertices[k]];
                const int slot = int(std::find(ring.ring, ring.ring + ring.count, neighbour) - ring.ring);
                out.ring_weights.push_back(slot < ring.count ? limit.positions.ring_weights[m->first + slot] : 0.0f);
            }
        }
    }
}

}  // namespace loopsub::detail
