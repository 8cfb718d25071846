// What the plan builder knows about one level besides its connectivity: the few sharp or tagged edges and vertices
// (features), and the walk over the vertices next to them, where the rules can differ from the smooth masks. Shared
// by the refinement levels (plan.cpp) and the limit (limit.cpp).
#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

#include "base/large_allocator.h"
#include "loopsub/loopsub.h"
#include "base/parallel.h"
#include "base/radix_sort.h"
#include "rules/rules.h"
#include "topology/topology.h"

namespace loopsub::detail {

// A sharp or tagged edge or vertex. Most of a mesh is smooth and untagged, so a level keeps only these, sorted by
// index: a creased model at level 4 has a few hundred of them among a million edges.
struct Feature {
    Index index;
    float sharpness;  // OpenSubdiv: the current sharpness; Hoppe94: infinite on creases and corners, else 0
    float tag;        // the crease or corner tag carried into the output (0: none)
    // An edge's ends, in its level's order. Carried from level to level (a half's are its parent's end and midpoint),
    // so that the walk over the features, the edge masks and the output's tags need not look them up (on a level that
    // is not built, a lookup goes through its parent's arrays).
    Index ends[2] = {-1, -1};
    bool operator<(const Feature& other) const { return index < other.index; }
};

inline const Feature* find_feature(const std::vector<Feature>& features, Index index) {
    const auto found = std::lower_bound(features.begin(), features.end(), Feature{index, 0.0f, 0.0f});
    return found != features.end() && found->index == index ? &*found : nullptr;
}

struct LevelState {
    Topology topology;
    bool own_neighbourhood = true;  // false: refined Rings or not built; its vertex neighbourhoods come from its parent
    std::vector<Feature> edges, vertices;

    float edge_sharpness(Index e) const {
        const Feature* f = find_feature(edges, e);
        return f ? f->sharpness : 0.0f;
    }
    float vertex_sharpness(Index v) const {
        const Feature* f = find_feature(vertices, v);
        return f ? f->sharpness : 0.0f;
    }
    float vertex_tag(Index v) const {
        const Feature* f = find_feature(vertices, v);
        return f ? f->tag : 0.0f;
    }
};

// A vertex next to a feature, with its edges (in VertexNeighbourhood order) and their sharpness and tags.
struct FeatureVertex {
    Index vertex;
    const std::vector<Index>& edges;
    const std::vector<float>& sharpness;
    const std::vector<float>& tags;
    int num_sharp_edges;           // how many of its edges are sharp
    Index crease[2];               // the first two sharp edges (-1: none)
    bool tagged_cone;              // Hoppe94
    const Feature* own = nullptr;  // the vertex's own sharpness and tag, where it is a feature itself
    // Per edge, its entry in the level's features (null: not a feature), so that what the vertex makes of it can go
    // to the feature's place in a list sorted like the features.
    const std::vector<const Feature*>* edge_features = nullptr;

    float own_sharpness() const { return own ? own->sharpness : 0.0f; }
    float own_tag() const { return own ? own->tag : 0.0f; }
};

// How many parts for_each_feature_vertex cuts its vertices into on `threads` threads: several per thread, taken in
// turn, as the vertices' work differs (a vertex on a crease gathers its sides' corners, one whose semi-sharp edges
// outlast the last level refines its ring on), and so does that of equal shares of them: threefold on the creased
// icosphere.
inline int feature_vertex_parts(int threads) { return threads < 2 ? 1 : kPiecesPerThread * threads; }

// Visits every vertex that touches a sharp or tagged edge, is tagged itself, or is a cone: visit(vertex, part), in
// vertex order within each of feature_vertex_parts(threads) parts, which run on `threads` threads and take
// consecutive ranges of vertices (a caller that collects per part and joins the parts in order keeps vertex order).
template <typename Visit>
void for_each_feature_vertex(const LevelState& level, const std::vector<Index>& cones,
                             const VertexNeighbourhood& around, Visit visit, int threads = 1) {
    // Each vertex meets its feature edges as a short run of (vertex, feature) pairs, so that gathering them needs
    // no search per incident edge. A pair is two indices, written in place: structs of pointers pushed one at a time
    // cost more and sorted three times as many bytes (docs/benchmark.md, "Measurements behind the code").
    struct Touch {
        Index vertex;
        Index feature;  // k >= 0: edge feature k; -2 - k: vertex feature k (the vertex itself); -1: a cone
    };
    LargeVector<Touch> touches(2 * level.edges.size() + level.vertices.size() + cones.size());
    Touch* next = touches.data();
    for (std::size_t k = 0; k < level.edges.size(); ++k) {
        *next++ = {level.edges[k].ends[0], Index(k)};
        *next++ = {level.edges[k].ends[1], Index(k)};
    }
    for (std::size_t k = 0; k < level.vertices.size(); ++k) *next++ = {level.vertices[k].index, -2 - Index(k)};
    for (Index v : cones)
        if (v < level.topology.num_vertices) *next++ = {v, -1};
    touches.resize(std::size_t(next - touches.data()));
    if (touches.empty()) return;
    // By vertex, a byte of the index at a time (stable, which the runs do not need), not by comparisons.
    radix_sort(touches, std::uint32_t(level.topology.num_vertices) - 1, [](const Touch& t) { return t.vertex; });

    auto visit_part = [&](int, int part, int part_count) {
        // A part starts where a vertex's run starts.
        auto run_start = [&touches](std::size_t i) {
            while (i > 0 && i < touches.size() && touches[i].vertex == touches[i - 1].vertex) ++i;
            return touches.begin() + std::ptrdiff_t(i);
        };
        const auto [first, last] = part_of(touches.size(), part, part_count);
        const auto end = run_start(last);
        std::vector<Index> edges;
        std::vector<float> sharpness, tags;
        std::vector<const Feature*> edge_features;
        for (auto run = run_start(first); run != end;) {
            const Index v = run->vertex;
            const auto run_end = std::find_if(run, end, [v](const Touch& touch) { return touch.vertex != v; });
            around.edges(v, edges);
            sharpness.assign(edges.size(), 0.0f);
            tags.assign(edges.size(), 0.0f);
            edge_features.assign(edges.size(), nullptr);
            const Feature* own = nullptr;
            for (auto touch = run; touch != run_end; ++touch) {
                if (touch->feature <= -2) own = &level.vertices[std::size_t(-2 - touch->feature)];
                if (touch->feature < 0) continue;
                const Feature& edge = level.edges[std::size_t(touch->feature)];
                const std::size_t k = std::size_t(std::find(edges.begin(), edges.end(), edge.index) - edges.begin());
                assert(k < edges.size());  // the feature's ends, carried from level to level, name this vertex
                sharpness[k] = edge.sharpness;
                tags[k] = edge.tag;
                edge_features[k] = &edge;
            }
            run = run_end;
            int num_sharp_edges = 0;
            Index crease[2] = {-1, -1};
            for (std::size_t k = 0; k < edges.size(); ++k)
                if (is_sharp(sharpness[k]) && num_sharp_edges++ < 2) crease[num_sharp_edges - 1] = edges[k];
            visit(FeatureVertex{v,
                                edges,
                                sharpness,
                                tags,
                                num_sharp_edges,
                                {crease[0], crease[1]},
                                std::binary_search(cones.begin(), cones.end(), v),
                                own,
                                &edge_features},
                  part);
        }
    };
    const int parts = feature_vertex_parts(threads);
    run_levels(threads, 1, visit_part, parts / std::max(1, threads));
}

// Hoppe 94's class of a vertex (hoppe94_vertex_type; docs/rules.md, "Vertex classes") from OpenSubdiv's rule and the
// cone tag, with the fan of a crease vertex read through `around`.
VertexType classify_vertex(SdcRule rule, const FeatureVertex& vertex, const VertexNeighbourhood& around);

}  // namespace loopsub::detail
