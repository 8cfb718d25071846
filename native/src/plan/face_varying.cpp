#include "plan/face_varying.h"

#include <algorithm>
#include <cassert>
#include <numeric>
#include <string>
#include <utility>

#include "base/common.h"
#include "base/parallel.h"

namespace loopsub::detail {

namespace {

using Mode = FaceVaryingInterpolation;

bool linear_boundaries(Mode mode) { return mode == Mode::Boundaries || mode == Mode::All; }
bool dependent_sharpness(Mode mode) { return mode == Mode::CornersPlus1 || mode == Mode::CornersPlus2; }

// The items (values or corners) of each vertex, in item order, as offsets into one list (CSR), from each item's vertex:
// a counting sort. In parts, each counts its own items, then places them after those of the parts before it, so that a
// vertex's items stay in item order whatever the number of parts.
void group_by_vertex(const Index* vertex_of, std::size_t items, int num_vertices, TransientVector<Index>& offsets,
                     TransientVector<Index>& grouped, int parts = 1) {
    offsets.resize(std::size_t(num_vertices) + 1);
    grouped.resize(items);
    if (parts == 1) {  // fewer passes than the parts' placing
        std::fill(offsets.begin(), offsets.end(), 0);
        for (std::size_t x = 0; x < items; ++x) ++offsets[std::size_t(vertex_of[x]) + 1];
        std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
        for (std::size_t x = 0; x < items; ++x) grouped[std::size_t(offsets[std::size_t(vertex_of[x])]++)] = Index(x);
        std::copy_backward(offsets.begin(), offsets.end() - 1,
                           offsets.end());  // each count was advanced to the next start
        offsets[0] = 0;
        return;
    }
    std::vector<TransientVector<Index>> counts(static_cast<std::size_t>(parts));
    std::vector<Index> range_items(std::size_t(parts), 0);  // items of the part's range of vertices
    run_levels(parts, 4, [&](int step, int part, int) {
        const auto [i0, i1] = part_of(items, part, parts);
        const auto [v0, v1] = part_of(num_vertices, part, parts);
        TransientVector<Index>& own = counts[std::size_t(part)];
        if (step == 0) {
            own.assign(std::size_t(num_vertices), 0);
            for (std::size_t i = i0; i < i1; ++i) ++own[std::size_t(vertex_of[i])];
        } else if (step == 1) {
            Index total = 0;
            for (const TransientVector<Index>& part_counts : counts)
                for (int v = v0; v < v1; ++v) total += part_counts[std::size_t(v)];
            range_items[std::size_t(part)] = total;
        } else if (step == 2) {  // the counts become each part's first place per vertex
            Index start = std::accumulate(range_items.begin(), range_items.begin() + part, Index(0));
            for (int v = v0; v < v1; ++v) {
                offsets[std::size_t(v)] = start;
                for (TransientVector<Index>& part_counts : counts)
                    start += std::exchange(part_counts[std::size_t(v)], start);
            }
            if (part + 1 == parts) offsets[std::size_t(num_vertices)] = start;
        } else {
            for (std::size_t i = i0; i < i1; ++i) grouped[std::size_t(own[std::size_t(vertex_of[i])]++)] = Index(i);
        }
    });
}

// A copy of `from`, in parts.
LargeVector<Index> copy_in_parts(const LargeVector<Index>& from, int parts) {
    LargeVector<Index> to(from.size());
    run_levels(parts, 1, [&](int, int part, int) {
        const auto [i0, i1] = part_of(from.size(), part, parts);
        std::copy(from.begin() + std::ptrdiff_t(i0), from.begin() + std::ptrdiff_t(i1),
                  to.begin() + std::ptrdiff_t(i0));
    });
    return to;
}

// The parts' lists one after the other, copied in parts where they are long (short lists, the usual masks, are not
// worth a meeting of the parts).
template <typename T, typename Parts, typename List>
void join_in_parts(const Parts& parts, List list, std::vector<T>& joined) {
    std::vector<std::size_t> starts(parts.size() + 1, 0);
    for (std::size_t p = 0; p < parts.size(); ++p) starts[p + 1] = starts[p] + list(parts[p]).size();
    joined.resize(starts.back());
    auto copy = [&](std::size_t part) {
        std::copy(list(parts[part]).begin(), list(parts[part]).end(), joined.begin() + std::ptrdiff_t(starts[part]));
    };
    if (starts.back() < 8192) {
        for (std::size_t part = 0; part < parts.size(); ++part) copy(part);
        return;
    }
    run_levels(int(parts.size()), 1, [&](int, int part, int) { copy(std::size_t(part)); });
}

// A value that stays where it is: the corner mask.
SpecialVertex copy_of(Index x) {
    const VertexMask corner = corner_vertex_mask();
    return {x, x, x, float(corner.self), float(corner.ring), float(corner.crease), float(corner.crease)};
}

}  // namespace

FaceVaryingBuilder::FaceVaryingBuilder(const MeshView& mesh, int layer, const Options& options, const LevelState& base)
    : options_(options),
      skip_level_before_last_(options.levels >= 2 && !options.limit_surface && options.face_varying != Mode::All) {
    const FaceVaryingLayer& input = mesh.face_varying[layer];  // checked with the mesh (validate_mesh)
    const std::size_t corners = 3 * std::size_t(mesh.num_triangles);
    plan_.num_input_values = input.num_values;

    // One layer vertex per (vertex, value) pair: a value index the caller shares between vertices becomes one
    // value per vertex, as in OpenSubdiv from level 1 on.
    // The corners in (vertex, value) order: grouped by vertex, then each vertex's few sorted by value (not a
    // comparison sort of all corners: docs/benchmark.md, "Measurements behind the code").
    TransientVector<Index> offsets, order;
    group_by_vertex(mesh.triangles, corners, mesh.num_vertices, offsets, order, parts_for(corners));
    auto value_of = [&](Index c) { return input.corner_values[c]; };
    const int parts = parts_for(corners);
    run_levels(parts, 1, [&](int, int part, int) {
        const auto [v0, v1] = part_of(mesh.num_vertices, part, parts);
        for (int v = v0; v < v1; ++v)
            std::sort(order.begin() + offsets[v], order.begin() + offsets[v + 1],
                      [&](Index a, Index b) { return value_of(a) < value_of(b); });
    });
    // A value per run of corners with the same (vertex, value): each part counts the runs that start in its corners,
    // then numbers them after those of the parts before.
    auto key = [&](Index c) { return std::pair<Index, Index>(mesh.triangles[c], value_of(c)); };
    auto starts_run = [&](std::size_t i) { return i == 0 || key(order[i]) != key(order[i - 1]); };
    std::vector<Index> runs(std::size_t(parts), 0);
    run_levels(parts, 1, [&](int, int part, int) {
        const auto [c0, c1] = part_of(corners, part, parts);
        Index count = 0;
        for (std::size_t i = c0; i < c1; ++i) count += starts_run(i);
        runs[std::size_t(part)] = count;
    });
    plan_.base_values.resize(std::size_t(std::accumulate(runs.begin(), runs.end(), Index(0))));
    TransientVector<Index> triangles(corners);
    run_levels(parts, 1, [&](int, int part, int) {
        const auto [c0, c1] = part_of(corners, part, parts);
        Index value = std::accumulate(runs.begin(), runs.begin() + part, Index(0)) - 1;  // the run c0 is in
        for (std::size_t i = c0; i < c1; ++i) {
            if (starts_run(i)) plan_.base_values[std::size_t(++value)] = input.corner_values[order[i]];
            triangles[order[i]] = value;
        }
    });
    values_ = build_base_topology(triangles.data(), mesh.num_triangles, int(plan_.base_values.size()), options.threads);
    plan_.counts.push_back(values_.num_vertices);
    map_to_vertices(base);
    classify_base(base);
    plan_.base_corner_values.assign(triangles.begin(), triangles.end());
    plan_.base_classes.resize(tags_.size());
    for (std::size_t x = 0; x < tags_.size(); ++x) {
        const Tag& tag = tags_[x];
        const FaceVaryingValueClass c = !tag.mismatch                     ? FaceVaryingValueClass::Vertex
                                        : tag.crease                      ? FaceVaryingValueClass::Seam
                                        : tag.semi_sharp || tag.dep_sharp ? FaceVaryingValueClass::Held
                                                                          : FaceVaryingValueClass::Stays;
        plan_.base_classes[x] = std::uint8_t(c);
    }
}

void FaceVaryingBuilder::map_to_vertices(const LevelState& base) {
    const Topology& t = base.topology;
    vertex_of_.resize(std::size_t(values_.num_vertices));
    edge_of_.resize(std::size_t(values_.num_edges()));
    split_.resize(std::size_t(t.num_edges()));
    const bool linear = linear_boundaries(options_.face_varying);
    // Face f of the layer is face f of the vertex mesh: a value's vertex and a layer edge's edge are those at the same
    // corner of one of its faces, and an edge is split where its faces' corners lie on different layer edges (a seam).
    auto corner_of = [](const LargeVector<Index>& of_faces, Index f, Index item) {
        const std::size_t c = 3 * std::size_t(f);
        return of_faces[c] == item ? c : of_faces[c + 1] == item ? c + 1 : c + 2;
    };
    const int parts = parts_for(values_.face_vertices.size());
    run_levels(parts, 1, [&](int, int part, int) {
        const auto [x0, x1] = part_of(values_.num_vertices, part, parts);
        for (Index x = x0; x < x1; ++x) {  // every value has a face: a corner made it
            const Index e = values_.vertex_edges[values_.vertex_edge_offsets[x]];
            vertex_of_[x] =
                t.face_vertices[corner_of(values_.face_vertices, values_.edge_faces[values_.edge_face_offsets[e]], x)];
        }
        const auto [l0, l1] = part_of(values_.num_edges(), part, parts);
        for (Index e = l0; e < l1; ++e)
            edge_of_[e] =
                t.face_edges[corner_of(values_.face_edges, values_.edge_faces[values_.edge_face_offsets[e]], e)];
        const auto [e0, e1] = part_of(t.num_edges(), part, parts);
        for (Index e = e0; e < e1; ++e) {
            const Index first = t.edge_face_offsets[e], end = t.edge_face_offsets[e + 1];
            const Index layer_edge = values_.face_edges[corner_of(t.face_edges, t.edge_faces[first], e)];
            bool split = linear && end - first == 1;
            for (Index k = first + 1; k < end && !split; ++k)
                split = values_.face_edges[corner_of(t.face_edges, t.edge_faces[k], e)] != layer_edge;
            split_[e] = split;
        }
    });
}

// Both meshes are refined by refine_topology, which numbers a level's children the same way on each: a child vertex
// per vertex, then one per edge; edge e's halves 2e (at its first end) and 2e + 1, then three edges inside each face,
// face by face. So a child value lies on its parent value's vertex or its layer edge's midpoint, a half of layer edge
// e is the half of e's edge at the same end, and an edge inside a face is the same edge inside the same face of the
// vertex mesh; the seams' halves are seams, the edges inside faces never are. This spares a pass over the child's
// corners, scattered writes to arrays a level's size (docs/benchmark.md, "Measurements behind the code").
void FaceVaryingBuilder::inherit_mapping(const Topology& t, const VertexNeighbourhood& vertex_level, int parts) {
    const Index nx = values_.num_vertices, layer_edges = values_.num_edges(), nv = t.num_vertices,
                ne = vertex_level.num_edges();
    // The vertex level may be known through its parent only (a limit planned from the last level's grandparent): its
    // faces are the layer's, its edge ends the neighbourhood's.
    const Index inside = 3 * Index(values_.num_faces());
    TransientVector<Index> vertex_of(std::size_t(nx) + layer_edges),
        edge_of(2 * std::size_t(layer_edges) + std::size_t(inside));
    TransientVector<std::uint8_t> split(2 * std::size_t(ne) + std::size_t(inside));
    assert(t.face_vertices.empty() || values_.num_faces() == t.num_faces());
    // Through local pointers: a store of a byte (split) may alias anything, and the loops would otherwise reload every
    // array's place after each.
    const Index* const parent_vertex_of = vertex_of_.data();
    const Index* const parent_edge_of = edge_of_.data();
    const std::uint8_t* const parent_split = split_.data();
    const Index* const layer_ends = values_.edge_vertices.data();
    Index* const child_vertex_of = vertex_of.data();
    Index* const child_edge_of = edge_of.data();
    std::uint8_t* const child_split = split.data();
    run_levels(parts, 1, [=, &vertex_level](int, int part, int) {
        const auto [x0, x1] = part_of(nx, part, parts);
        std::copy(parent_vertex_of + x0, parent_vertex_of + x1, child_vertex_of + x0);
        const auto [e0, e1] = part_of(layer_edges, part, parts);
        for (Index e = e0; e < e1; ++e) {
            const Index edge = parent_edge_of[e];
            Index ends[2];
            vertex_level.edge_ends(edge, ends);
            const bool same_way = parent_vertex_of[layer_ends[2 * std::size_t(e)]] == ends[0];
            assert(parent_vertex_of[layer_ends[2 * std::size_t(e) + (same_way ? 1 : 0)]] == ends[1]);
            child_vertex_of[std::size_t(nx) + std::size_t(e)] = nv + edge;
            child_edge_of[2 * std::size_t(e)] = 2 * edge + (same_way ? 0 : 1);
            child_edge_of[2 * std::size_t(e) + 1] = 2 * edge + (same_way ? 1 : 0);
        }
        const auto [k0, k1] = part_of(inside, part, parts);
        for (Index k = k0; k < k1; ++k) child_edge_of[2 * std::size_t(layer_edges) + std::size_t(k)] = 2 * ne + k;
        std::fill(child_split + 2 * std::size_t(ne) + std::size_t(k0),
                  child_split + 2 * std::size_t(ne) + std::size_t(k1), std::uint8_t(0));
        const auto [E0, E1] = part_of(ne, part, parts);
        for (Index e = E0; e < E1; ++e)
            child_split[2 * std::size_t(e)] = child_split[2 * std::size_t(e) + 1] = parent_split[e];
    });
    vertex_of_ = std::move(vertex_of);
    edge_of_ = std::move(edge_of);
    split_ = std::move(split);
}

int FaceVaryingBuilder::parts_for(std::size_t items) const { return items >= 8192 ? std::max(1, options_.threads) : 1; }

const std::vector<Index>& FaceVaryingBuilder::edges_at(Index x, Walk& walk) const {
    layer().edges(x, walk.edges);
    return walk.edges;
}

void FaceVaryingBuilder::inner_edges(Index x, std::vector<Index>& edges, Walk& walk) const {
    const VertexNeighbourhood layer = this->layer();
    edges.clear();
    for (Index e : edges_at(x, walk))
        if (layer.edge_face_count(e) == 2) edges.push_back(edge_of_[e]);
}

bool FaceVaryingBuilder::seam_ends(Index x, Index ends[2], Walk& walk) const {
    const VertexNeighbourhood layer = this->layer();
    int found = 0;
    for (Index e : edges_at(x, walk)) {
        if (layer.edge_face_count(e) != 1) continue;
        if (found < 2) ends[found] = layer.other_end(e, x);
        ++found;
    }
    return found == 2;
}

template <typename InnerSemi>
void FaceVaryingBuilder::release_held_values(Mode mode, Tag* const* child_tags, int n, bool child_semi_edges,
                                             InnerSemi inner_semi) {
    for (int i = 0; i < n; ++i) {
        Tag& tag = *child_tags[i];
        if (!tag.semi_sharp) continue;
        if (child_semi_edges && (tag.dep_sharp || inner_semi(i))) continue;
        tag.crease = true;
        tag.semi_sharp = tag.dep_sharp = false;
    }
    if (n == 2 && dependent_sharpness(mode)) {
        Tag& first = *child_tags[0];
        Tag& second = *child_tags[1];
        if (first.dep_sharp && !second.semi_sharp) first.dep_sharp = false;
        else if (second.dep_sharp && !first.semi_sharp) second.dep_sharp = false;
    }
}

SpecialVertex FaceVaryingBuilder::on_layer(Index x, const SpecialVertex& m, Walk& walk) const {
    const Index a = m.w_crease_a != 0.0f ? neighbour_at_vertex(x, m.crease_a, walk) : x;
    const Index b = m.w_crease_b != 0.0f ? neighbour_at_vertex(x, m.crease_b, walk) : x;
    return {x, a < 0 ? x : a, b < 0 ? x : b, m.w_self, m.w_ring, m.w_crease_a, m.w_crease_b};
}

Index FaceVaryingBuilder::neighbour_at_vertex(Index x, Index vertex, Walk& walk) const {
    const VertexNeighbourhood layer = this->layer();
    for (Index e : edges_at(x, walk)) {
        const Index other = layer.other_end(e, x);
        if (vertex_of_[other] == vertex) return other;
    }
    return -1;
}

// Vtr::FVarLevel::completeTopologyFromFaceValues: which values follow the seam rules, and how; the vertices in parts,
// each writing its own values' tags.
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

    const bool linear_b = linear_boundaries(mode), dependent = dependent_sharpness(mode),
               plus2 = mode == Mode::CornersPlus2;
    const bool sharp_darts = plus2 || linear_b, sharp_fan_corners = mode != Mode::None;
    struct Span {
        int faces = 0, infinite = 0, semi = 0;
        bool disjoint = false;
    };
    const int parts = parts_for(std::size_t(values_.num_vertices));
    run_levels(parts, 1, [&](int, int part, int) {
        Walk walk;
        std::vector<Span> spans;
        const auto [v0, v1] = part_of(t.num_vertices, part, parts);
        for (int v = v0; v < v1; ++v) {
            const int n = offsets[v + 1] - offsets[v];
            if (n == 0) continue;
            const Index* values = at_vertex.data() + offsets[v];
            bool boundary = false, seam = false;
            int face_corners = 0;
            for (Index k = t.vertex_edge_offsets[v]; k < t.vertex_edge_offsets[v + 1]; ++k) {
                const Index e = t.vertex_edges[k];
                boundary |= t.edge_face_count(e) == 1;
                seam |= split_[e] != 0;
                face_corners += t.edge_face_count(e);
            }
            const bool one_face_corner = boundary && face_corners == 2;
            const bool mismatched =
                seam || (linear_b && boundary) ||
                (one_face_corner && mode != Mode::None && options_.boundary != Boundary::EdgesAndCorners) ||
                (vertex_non_manifold[v] && n >= 2);
            if (!mismatched) continue;
            for (int i = 0; i < n; ++i) tags_[values[i]].mismatch = true;
            if (vertex_non_manifold[v]) continue;  // every value stays

            spans.assign(n, Span{});
            for (int i = 0; i < n; ++i) {
                const Index x = values[i];
                Span& span = spans[i];
                for (Index e : edges_at(x, walk)) span.faces += values_.edge_face_count(e);
                span.faces /= 2;
                inner_edges(x, walk.inner, walk);
                for (Index e : walk.inner) {
                    const float sharpness = base.edge_sharpness(e);
                    span.infinite += is_infinite(sharpness);
                    span.semi += is_semi_sharp(sharpness);
                }
                span.disjoint = value_non_manifold[x] != 0;  // its faces are not one fan, or a seam ends inside it
            }
            const float vertex_sharpness = base.vertex_sharpness(v);
            bool all_sharp = linear_b || is_infinite(vertex_sharpness) || (dependent && n > 2) ||
                             (sharp_darts && n == 1 && !boundary);
            bool sharpen_dependent = false;
            if (!all_sharp && dependent && n == 2) {
                all_sharp = spans[0].infinite || spans[1].infinite || spans[0].disjoint || spans[1].disjoint;
                if (plus2) all_sharp |= spans[0].faces == 1 || spans[1].faces == 1;
                sharpen_dependent = (spans[0].semi > 0) != (spans[1].semi > 0);
            }
            for (int i = 0; i < n; ++i) {
                Tag& tag = tags_[values[i]];
                const Span& span = spans[i];
                if (span.disjoint || all_sharp || span.infinite > 0 || (span.faces == 1 && sharp_fan_corners)) continue;
                if (span.semi > 0 || is_semi_sharp(vertex_sharpness)) tag.semi_sharp = true;
                else if (sharpen_dependent) tag.semi_sharp = tag.dep_sharp = true;
                else tag.crease = true;
            }
        }
    });
}

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
    tags_ = std::move(child_tags);
    plan_.counts.push_back(values_.num_vertices);
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
        if (!parent_semi || is_sharp(child.vertex_sharpness(v))) continue;
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

// Value points of values [x0, x1), in value order.
void FaceVaryingBuilder::plan_value_points(const LevelState& level, const LevelState& child,
                                           const VertexNeighbourhood& vertex_level,
                                           const TransientVector<Index>& offsets,
                                           const TransientVector<Index>& at_vertex,
                                           const SpecialsByTarget<SpecialVertex>& special_vertex,
                                           const TransientVector<Tag>& child_tags, Index x0, Index x1,
                                           std::vector<SpecialVertex>& out, Walk& walk) const {
    auto child_sharpness_at = [&](Index e, Index v) { return child.edge_sharpness(vertex_level.child_edge_at(e, v)); };
    for (Index x = x0; x < x1; ++x) {
        const Tag& tag = tags_[x];
        const Index v = vertex_of_[x];
        if (!tag.mismatch) {
            const SpecialVertex* m = special_vertex[v];
            if (m) out.push_back(on_layer(x, *m, walk));  // else the smooth mask, by the same valence
            continue;
        }
        Index ends[2];
        if (!child_tags[x].crease || !seam_ends(x, ends, walk)) {
            out.push_back(copy_of(x));
            continue;
        }
        VertexMask mask = crease_vertex_mask();
        if (tag.semi_sharp) {
            // The weight of the held position, from the features that decayed this level: the value's own span,
            // or its sibling's when it was held for the sibling.
            Index span = x;
            if (tag.dep_sharp)
                for (Index k = offsets[v]; k < offsets[v + 1]; ++k)
                    if (at_vertex[k] != x) span = at_vertex[k];
            inner_edges(span, walk.inner, walk);
            walk.parent_edges.clear();
            walk.child_edges.clear();
            for (Index e : walk.inner) {
                walk.parent_edges.push_back(level.edge_sharpness(e));
                walk.child_edges.push_back(child_sharpness_at(e, v));
            }
            const float w =
                transition_weight(options_.crease_method, level.vertex_sharpness(v), child.vertex_sharpness(v),
                                  walk.parent_edges.data(), walk.child_edges.data(), int(walk.inner.size()));
            mask = blend(corner_vertex_mask(), w, mask);  // held (a corner) by w, the seam's crease the rest
        }
        out.push_back(
            {x, ends[0], ends[1], float(mask.self), float(mask.ring), float(mask.crease), float(mask.crease)});
    }
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
    const Tag on_seam{true, !linear_boundaries(mode), false, false};
    for (Index e = e0; e < e1; ++e) {
        const Index edge = edge_of[e];
        const bool split = seam[edge] || mode == Mode::All;
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
            out.vertices.push_back(copy_of(x));
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

FaceVaryingPlan FaceVaryingBuilder::finish() {
    assert(std::all_of(plan_.passes.begin(), plan_.passes.end(), follows_table_layout));
    plan_.output_corner_values = std::move(values_.face_vertices);
    return std::move(plan_);
}

}  // namespace loopsub::detail
