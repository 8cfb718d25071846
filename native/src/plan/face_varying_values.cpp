// A face-varying layer's values: one per (vertex, value) pair of the input, numbered from the corners; their maps to
// the vertex mesh (a value's vertex, a layer edge's edge, the seams), made at the base level and inherited through
// each split's numbering; and the helpers the builder's files share (face_varying_parts.h).
#include <algorithm>
#include <cassert>
#include <numeric>
#include <utility>

#include "base/common.h"
#include "base/parallel.h"
#include "plan/face_varying.h"
#include "plan/face_varying_parts.h"
#include "rules/face_varying_rules.h"

namespace loopsub::detail {

void group_by_vertex(const Index* vertex_of, std::size_t items, int num_vertices, TransientVector<Index>& offsets,
                     TransientVector<Index>& grouped, int parts) {
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

LargeVector<Index> copy_in_parts(const LargeVector<Index>& from, int parts) {
    LargeVector<Index> to(from.size());
    run_levels(parts, 1, [&](int, int part, int) {
        const auto [i0, i1] = part_of(from.size(), part, parts);
        std::copy(from.begin() + std::ptrdiff_t(i0), from.begin() + std::ptrdiff_t(i1),
                  to.begin() + std::ptrdiff_t(i0));
    });
    return to;
}

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
    for (std::size_t x = 0; x < tags_.size(); ++x)
        plan_.base_classes[x] = std::uint8_t(face_varying_value_class(tags_[x]));
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

FaceVaryingPlan FaceVaryingBuilder::finish() {
    assert(std::all_of(plan_.passes.begin(), plan_.passes.end(), follows_table_layout));
    plan_.output_corner_values = std::move(values_.face_vertices);
    return std::move(plan_);
}

}  // namespace loopsub::detail
