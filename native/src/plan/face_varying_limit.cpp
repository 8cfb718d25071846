// The limit pass of a face-varying layer: where each value of the last level goes (its vertex's limit, its seam's, or
// where it is), and where a value held by semi-sharp features that outlast the last level goes once they are spent.
#include <algorithm>
#include <vector>

#include "base/parallel.h"
#include "plan/face_varying.h"
#include "plan/face_varying_parts.h"
#include "rules/face_varying_rules.h"

namespace loopsub::detail {

// A value held on the last level by semi-sharp features that outlast it, with its refinement so far.
struct FaceVaryingBuilder::Held {
    Index value, ends[2];
    double refinement[3][3];  // (value, end a, end b) down to where it follows the seam, or for good
    bool released;
};

// What the hold at one vertex reads level after level: its edges (every one lies in some value's span) with their
// sharpness on the current level and the next, each value's inner edges among them (as slots), its own sharpness,
// and its values' tags.
struct FaceVaryingBuilder::HeldVertex {
    const Index* values = nullptr;
    int n = 0;
    std::vector<Index> edges;
    std::vector<std::vector<int>> inner_slots;
    std::vector<float> sharpness, child_sharpness, parent_inner, child_inner;
    float vertex_sharpness = 0.0f;
    std::vector<Tag> tags, child_tags;
    std::vector<Tag*> value_tags;
};

// Where a value held on the last level goes: held until its features are spent, then along its seam. Its vertex's
// features decay level after level as plan_level would go on, in closed form over the value and its two seam ends.
void FaceVaryingBuilder::plan_held_limits(const LevelState& last, const RuleSet& rules, LevelStencils& s) const {
    if (options_.face_varying == Mode::All) return;
    Walk walk;
    TransientVector<Index> offsets, at_vertex;
    group_by_vertex(vertex_of_.data(), vertex_of_.size(), last.topology.num_vertices, offsets, at_vertex,
                    parts_for(vertex_of_.size()));
    HeldVertex at;
    std::vector<Held> held;
    for (int v = 0; v < last.topology.num_vertices; ++v) {
        at.n = offsets[v + 1] - offsets[v];
        at.values = at_vertex.data() + offsets[v];
        if (!std::any_of(at.values, at.values + at.n,
                         [&](Index x) { return tags_[x].mismatch && tags_[x].semi_sharp; }))
            continue;
        const std::size_t first_held = held.size();
        gather_held(v, last, at, held, walk);
        // Until every held value follows its seam or nothing decays any more.
        auto all_released = [&] {
            return std::all_of(held.begin() + first_held, held.end(), [](const Held& h) { return h.released; });
        };
        while (!all_released() && (is_semi_sharp(at.vertex_sharpness) ||
                                   std::any_of(at.sharpness.begin(), at.sharpness.end(), is_semi_sharp)))
            hold_one_level(rules, at, held.data() + first_held, held.data() + held.size());
    }
    // A released value goes to its seam's limit, one held for good stays.
    for (const Held& h : held) {
        const LimitMask limit = face_varying_held_limit_mask(h.released);
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

// Vertex v's edges and their sharpness, its values' inner edges and tags, and its held values (those with two seam
// neighbours) appended to `held`.
void FaceVaryingBuilder::gather_held(Index v, const LevelState& last, HeldVertex& at, std::vector<Held>& held,
                                     Walk& walk) const {
    const int n = at.n;
    at.edges.clear();
    for (int i = 0; i < n; ++i)
        for (Index e : edges_at(at.values[i], walk)) at.edges.push_back(edge_of_[e]);
    std::sort(at.edges.begin(), at.edges.end());
    at.edges.erase(std::unique(at.edges.begin(), at.edges.end()), at.edges.end());
    at.inner_slots.assign(n, {});
    for (int i = 0; i < n; ++i) {
        inner_edges(at.values[i], walk.inner, walk);
        for (Index e : walk.inner)
            at.inner_slots[i].push_back(int(std::lower_bound(at.edges.begin(), at.edges.end(), e) - at.edges.begin()));
    }
    at.sharpness.clear();
    for (Index e : at.edges) at.sharpness.push_back(last.edge_sharpness(e));
    at.vertex_sharpness = last.vertex_sharpness(v);
    at.tags.assign(n, Tag{});
    for (int i = 0; i < n; ++i) at.tags[i] = tags_[at.values[i]];
    for (int i = 0; i < n; ++i) {
        Held h{at.values[i], {-1, -1}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, false};
        if (at.tags[i].semi_sharp && seam_ends(at.values[i], h.ends, walk)) held.push_back(h);
    }
}

// One level of the hold at a vertex, as plan_level plans it: the sharpness decays, held values are released by the
// rules (release_held_values), and each held value's refinement takes the level's step: its mask over itself and its
// seam ends, whose midpoints are its next ends.
void FaceVaryingBuilder::hold_one_level(const RuleSet& rules, HeldVertex& at, Held* first, Held* last) const {
    const Mode mode = options_.face_varying;
    const int n = at.n;
    const float child_vertex = rules.child_vertex_sharpness(at.vertex_sharpness);
    at.child_sharpness.resize(at.sharpness.size());
    for (std::size_t k = 0; k < at.sharpness.size(); ++k)
        at.child_sharpness[k] =
            rules.child_edge_sharpness(at.sharpness[k], at.sharpness.data(), int(at.sharpness.size()));
    at.child_tags = at.tags;
    auto is_semi_slot = [&at](const std::vector<int>& slots) {
        return std::any_of(slots.begin(), slots.end(), [&](int k) { return is_semi_sharp(at.child_sharpness[k]); });
    };
    if (!is_sharp(child_vertex)) {
        at.value_tags.clear();
        for (Tag& tag : at.child_tags) at.value_tags.push_back(&tag);
        release_held_values(mode, at.value_tags.data(), n,
                            std::any_of(at.child_sharpness.begin(), at.child_sharpness.end(), is_semi_sharp),
                            [&](int i) { return is_semi_slot(at.inner_slots[i]); });
    }
    for (Held* value = first; value != last; ++value) {
        if (value->released) continue;
        const int i = int(std::find(at.values, at.values + n, value->value) - at.values);
        VertexMask mask = corner_vertex_mask();
        if (at.child_tags[i].crease) {
            // Blended with the hold by what decayed in its span, or its sibling's (plan_level's weight).
            at.parent_inner.clear();
            at.child_inner.clear();
            for (int k : at.inner_slots[face_varying_weight_span(at.tags[i], i, n)])
                at.parent_inner.push_back(at.sharpness[k]), at.child_inner.push_back(at.child_sharpness[k]);
            const float w =
                transition_weight(options_.crease_method, at.vertex_sharpness, child_vertex, at.parent_inner.data(),
                                  at.child_inner.data(), int(at.parent_inner.size()));
            mask = face_varying_seam_mask(at.tags[i].semi_sharp, w);
            value->released = true;
        }
        const EdgeMask seam = crease_edge_mask();
        const double step[3][3] = {{mask.self, mask.crease, mask.crease}, {seam.a, seam.b, 0.0}, {seam.a, 0.0, seam.b}};
        double product[3][3];
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c)
                product[r][c] = step[r][0] * value->refinement[0][c] + step[r][1] * value->refinement[1][c] +
                                step[r][2] * value->refinement[2][c];
        std::copy(&product[0][0], &product[0][0] + 9, &value->refinement[0][0]);
    }
    at.tags.swap(at.child_tags);
    at.sharpness.swap(at.child_sharpness);
    at.vertex_sharpness = child_vertex;
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
        if (next_held != held + num_held && next_held->vertex == x) {
            ++next_held;  // plan_held_limits' already
            continue;
        }
        Index ends[2];
        switch (face_varying_limit(mode, tags_[x], [&] { return seam_ends(x, ends, walk); })) {
            case FaceVaryingLimit::Stays: out.vertices.push_back(staying_value(x)); break;
            case FaceVaryingLimit::Seam:
                out.vertices.push_back(
                    {x, ends[0], ends[1], float(crease.self), 0.0f, float(crease.end_a), float(crease.end_b)});
                break;
            case FaceVaryingLimit::Vertex:
                if (const SpecialVertex* m = special_vertex[std::size_t(vertex_of_[x])]) {
                    out.vertices.push_back(on_layer(x, *m, walk));
                } else if (const RingWeightedVertex* w = ring_weighted[std::size_t(vertex_of_[x])]) {
                    // Without a seam at the vertex, the value's ring is the vertex's, value for neighbour, in its own
                    // order.
                    Index buffer[6];
                    const LimitRing ring = limit_ring(limit, w->vertex, buffer);
                    out.ring_weighted.push_back({x, Index(out.ring_weights.size()), w->w_self});
                    for (Index k = values_.vertex_edge_offsets[x]; k < values_.vertex_edge_offsets[x + 1]; ++k) {
                        const Index neighbour = vertex_of_[values_.vertex_vertices[k]];
                        const int slot = int(std::find(ring.ring, ring.ring + ring.count, neighbour) - ring.ring);
                        out.ring_weights.push_back(slot < ring.count ? limit.positions.ring_weights[w->first + slot]
                                                                     : 0.0f);
                    }
                }
                break;
        }
    }
}

}  // namespace loopsub::detail
