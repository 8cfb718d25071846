// One level of a face-varying layer: its value points and edge points beside the vertex plan's masks, the children's
// tags, and the layer's next level (built, or read through this one where the level before the last is not built).
#include <algorithm>
#include <cassert>
#include <vector>

#include "base/parallel.h"
#include "plan/face_varying.h"
#include "plan/face_varying_parts.h"
#include "rules/face_varying_rules.h"

namespace loopsub::detail {

void FaceVaryingBuilder::plan_level(const LevelState& level, const Topology* level_parent,
                                    const LevelStencils& vertex_stencils, const LevelState& child, bool last) {
    const Topology& t = level.topology;
    const VertexNeighbourhood vertex_level(t, level_parent);
    const VertexNeighbourhood layer = this->layer();
    const int nx = values_.num_vertices, ne = layer.num_edges();
    const bool child_not_built = skip_level_before_last_ && int(plan_.passes.size()) + 2 == options_.levels;
    LevelStencils& s = plan_.passes.emplace_back();
    s.num_vertices = nx;
    s.num_edges = ne;
    set_smooth_masks(s, layer.max_valence(), smooth_vertex_mask);

    // The children's tags: a vertex's child keeps its parent's, except that semi-sharp values turn into creases as
    // the sharpness around them decays (Vtr::FVarRefinement::reclassifySemisharpValues).
    // Tags of the edges' children too only when a level is planned on this one's children.
    const bool planned_further = !last || options_.limit_surface;
    TransientVector<Tag> child_tags(std::size_t(nx) + (planned_further ? ne : 0));
    const int parts = parts_for(std::size_t(nx) + std::size_t(ne));
    TransientVector<Index> offsets, at_vertex;
    group_by_vertex(vertex_of_.data(), vertex_of_.size(), t.num_vertices, offsets, at_vertex, parts);
    SpecialsByTarget<SpecialVertex> special_vertex(vertex_stencils.special_vertices, vertex_stencils.num_vertices,
                                                   [](const SpecialVertex& sv) { return sv.vertex; });
    SpecialsByTarget<SpecialEdge> special_edge(vertex_stencils.special_edges, vertex_stencils.num_edges,
                                               [](const SpecialEdge& se) { return se.edge; });

    // Three steps, each in parts of the values, vertices and edges: every part writes its own values' and edges'
    // tags and masks, and the masks are joined in part order, so that any number of parts plans the same level.
    std::vector<PartOutput> outputs(static_cast<std::size_t>(parts));
    run_levels(parts, 3, [&](int step, int part, int) {
        Walk walk;
        const auto [x0, x1] = part_of(nx, part, parts);
        const auto [e0, e1] = part_of(ne, part, parts);
        if (step == 0) {
            std::copy(tags_.begin() + x0, tags_.begin() + x1, child_tags.begin() + x0);
            const auto [v0, v1] = part_of(vertex_stencils.num_vertices, part, parts);
            special_vertex.mark(v0, v1);
            const auto [edge0, edge1] = part_of(vertex_stencils.num_edges, part, parts);
            special_edge.mark(edge0, edge1);
        } else if (step == 1) {
            const auto [v0, v1] = part_of(t.num_vertices, part, parts);
            release_values(level, child, vertex_level, offsets, at_vertex, v0, v1, child_tags, walk);
        } else {
            plan_value_points(level, child, vertex_level, offsets, at_vertex, special_vertex, child_tags, x0, x1,
                              outputs[std::size_t(part)].vertices, walk);
            plan_edge_points(vertex_level, special_edge, planned_further, e0, e1, child_tags,
                             outputs[std::size_t(part)].edges);
        }
    });
    join_in_parts(
        outputs, [](const PartOutput& out) -> const std::vector<SpecialVertex>& { return out.vertices; },
        s.special_vertices);
    join_in_parts(
        outputs, [](const PartOutput& out) -> const std::vector<SpecialEdge>& { return out.edges; }, s.special_edges);

    refine_values(t, vertex_level, s, planned_further, child_not_built, parts);
    tags_ = std::move(child_tags);
    plan_.counts.push_back(values_.num_vertices);
}

// The layer's next level: refined (faces only where nothing is planned on it), or not built where it is the level
// before the last (then read through this one, which keeps its offsets and edges); this level's arrays go to its
// tables `s`, and its maps to the next level's.
void FaceVaryingBuilder::refine_values(const Topology& t, const VertexNeighbourhood& vertex_level, LevelStencils& s,
                                       bool planned_further, bool child_not_built, int parts) {
    const int nx = values_.num_vertices, ne = this->layer().num_edges();
    Topology child_values;
    if (!values_built_) {
        // The level before the last: its tables from its parent, and the last level's faces with them.
        child_values.num_vertices = nx + ne;
        child_values.face_vertices.resize(48 * std::size_t(parent_values_.num_faces()));
        fill_tables_from_parent(parent_values_, s, child_values.face_vertices.data(), options_.threads);
        s.fan_first_midpoint = parent_values_.num_vertices;
        s.fan_midpoints = parent_values_.num_edges();
        s.interior->face_vertices = std::move(parent_values_.face_vertices);
        s.interior->face_edges = std::move(parent_values_.face_edges);
        parent_values_ = Topology();
    } else {
        if (child_not_built) child_values.num_vertices = nx + ne;
        else
            child_values =
                refine_topology(values_, planned_further ? Refined::Full : Refined::FacesOnly, options_.threads);
        if (planned_further) inherit_mapping(t, vertex_level, parts);
        // A child not built is read through this level: it keeps its offsets and edges (copies to the tables).
        if (child_not_built)
            s.ring_offsets = copy_in_parts(values_.vertex_edge_offsets, parts),
            s.edge_ends = copy_in_parts(values_.edge_vertices, parts);
        else s.ring_offsets = std::move(values_.vertex_edge_offsets), s.edge_ends = std::move(values_.edge_vertices);
        s.ring = std::move(values_.vertex_vertices);
        s.edge_wing_c = std::move(values_.edge_wing_c);
        s.edge_wing_d = std::move(values_.edge_wing_d);
        if (child_not_built) parent_values_ = std::move(values_);
    }
    values_built_ = !child_not_built;
    values_ = std::move(child_values);
}

// Value points of values [x0, x1), in value order.
void FaceVaryingBuilder::plan_value_points(const LevelState& level, const LevelState& child,
                                           const VertexNeighbourhood& vertex_level,
                                           const TransientVector<Index>& offsets,
                                           const TransientVector<Index>& at_vertex,
                                           const SpecialsByTarget<SpecialVertex>& special_vertex,
                                           const TransientVector<Tag>& child_tags, Index x0, Index x1,
                                           std::vector<SpecialVertex>& out, Walk& walk) const {
    for (Index x = x0; x < x1; ++x) {
        const Tag& tag = tags_[x];
        const Index v = vertex_of_[x];
        if (!tag.mismatch) {
            const SpecialVertex* m = special_vertex[v];
            if (m) out.push_back(on_layer(x, *m, walk));  // else the smooth mask, by the same valence
            continue;
        }
        Index ends[2];
        if (!face_varying_follows_seam(child_tags[x], [&] { return seam_ends(x, ends, walk); })) {
            out.push_back(staying_value(x));
            continue;
        }
        const double hold = tag.semi_sharp ? hold_weight(level, child, vertex_level, offsets, at_vertex, x, walk) : 0.0;
        const VertexMask mask = face_varying_seam_mask(tag.semi_sharp, hold);
        out.push_back(
            {x, ends[0], ends[1], float(mask.self), float(mask.ring), float(mask.crease), float(mask.crease)});
    }
}

// The weight of value x's held position as it is released, Sdc's transition weight of the features that decayed this
// level in its weight span (face_varying_weight_span: its own, or its sibling's where it was held for the sibling).
float FaceVaryingBuilder::hold_weight(const LevelState& level, const LevelState& child,
                                      const VertexNeighbourhood& vertex_level, const TransientVector<Index>& offsets,
                                      const TransientVector<Index>& at_vertex, Index x, Walk& walk) const {
    const Index v = vertex_of_[x];
    const Index* values = at_vertex.data() + offsets[v];
    const int n = offsets[v + 1] - offsets[v];
    assert(!tags_[x].dep_sharp || n == 2);  // the rules hold a value for its sibling only between two
    const Index span = values[face_varying_weight_span(tags_[x], int(std::find(values, values + n, x) - values), n)];
    inner_edges(span, walk.inner, walk);
    walk.parent_edges.clear();
    walk.child_edges.clear();
    for (Index e : walk.inner) {
        walk.parent_edges.push_back(level.edge_sharpness(e));
        walk.child_edges.push_back(child.edge_sharpness(vertex_level.child_edge_at(e, v)));
    }
    return transition_weight(options_.crease_method, level.vertex_sharpness(v), child.vertex_sharpness(v),
                             walk.parent_edges.data(), walk.child_edges.data(), int(walk.inner.size()));
}

// Edge points of layer edges [e0, e1): midpoints along seams, the edge's own mask elsewhere. Their children on a seam
// follow it (smooth modes) or stay (linear boundaries); the rest match.
void FaceVaryingBuilder::plan_edge_points(const VertexNeighbourhood& vertex_level,
                                          const SpecialsByTarget<SpecialEdge>& special_edge, bool planned_further,
                                          Index e0, Index e1, TransientVector<Tag>& child_tags,
                                          std::vector<SpecialEdge>& out) const {
    const Mode mode = options_.face_varying;
    const VertexNeighbourhood layer = this->layer();
    // Through local pointers: a tag's bytes may alias anything, and the arrays' places would be loaded again after
    // each store.
    const Index* edge_of = edge_of_.data();
    const std::uint8_t* seam = split_.data();
    Tag* edge_child_tags = child_tags.data() + values_.num_vertices;
    const Tag on_seam = face_varying_midpoint_tag(mode);
    for (Index e = e0; e < e1; ++e) {
        const Index edge = edge_of[e];
        const bool split = face_varying_edge_on_seam(mode, seam[edge] != 0);
        if (planned_further) edge_child_tags[e] = split ? on_seam : Tag{};
        if (split) {
            const EdgeMask mask = crease_edge_mask();  // the midpoint
            out.push_back({e, float(mask.a), float(mask.b), float(mask.wings)});
            continue;
        }
        const SpecialEdge* m = special_edge[edge];
        if (!m) continue;
        Index ends[2], layer_ends[2];
        vertex_level.edge_ends(edge, ends);
        layer.edge_ends(e, layer_ends);
        const bool same_way = vertex_of_[layer_ends[0]] == ends[0];
        out.push_back({e, same_way ? m->wa : m->wb, same_way ? m->wb : m->wa, m->wcd});
    }
}

}  // namespace loopsub::detail
