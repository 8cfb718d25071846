// Face-varying layers (UVs with seams), planned level by level beside the vertex plan (OpenSubdiv's FVarLevel and
// FVarRefinement in spirit).
//
// A layer is refined as a mesh of its own: one vertex per (vertex, value) pair, the triangles as the input's, so
// that a seam is a boundary of this mesh and each side refines from its own values with the same Loop split and
// numbering (refine_topology; its level before the last, as the vertex mesh's, is not built but filled from its
// parent). Face f of the layer is face f of the vertex mesh at every level, which maps each value to its vertex and
// each layer edge to its edge through the corners. The masks then come from two sources:
//   * a value whose vertex has no seam ("matching") takes the vertex's own mask from the vertex plan, its
//     neighbours read through the layer: creases, semi-sharp blends, Hoppe 94's classes all carry over;
//   * values on a seam follow Options::face_varying: corners stay, the rest runs along the seam as a uniform cubic
//     B-spline (1, 6, 1) / 8 with midpoints on the seam's edges, semi-sharp features blending in as they decay.
// The classification at the base level and its inheritance follow OpenSubdiv 3.5 (Vtr::FVarLevel), so that
// values equal Far::PrimvarRefiner::InterpolateFaceVarying / LimitFaceVarying; the seam rules themselves are
// rules/face_varying_rules.h's. FaceVaryingBuilder's code, one role a file: face_varying_values.cpp (the values and
// their maps), face_varying_walks.cpp, face_varying_classes.cpp (the facts the rules read, the tags),
// face_varying_level.cpp, face_varying_limit.cpp.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstdint>
#include <vector>

#include "plan/level_state.h"
#include "rules/face_varying_rules.h"
#include "rules/rule_set.h"
#include "tables/limit_tables.h"
#include "tables/stencils.h"

namespace loopsub::detail {

struct FaceVaryingPlan {
    int num_input_values = 0;
    LargeVector<Index> base_values;           // per value of the layer's base mesh: the caller's value index
    std::vector<Index> base_corner_values;    // 3 per input triangle: the base mesh's value at each corner
    std::vector<std::uint8_t> base_classes;   // per base value: its FaceVaryingValueClass at the base level
    std::vector<LevelStencils> passes;        // one per level, then the limit
    std::vector<int> counts;                  // values before each pass, and after the last
    LargeVector<Index> output_corner_values;  // 3 per output triangle
};

// The vertex plan's special masks of one kind (`specials`, sorted by target: vertex or edge), looked up by target: a
// byte per target says whether it has one, which a binary search of the list then finds (few targets have one). A
// pointer per target made a table eight times the size, zeroed and read for every value and edge of a level
// (docs/benchmark.md). Marked in parts: each part of a level's targets marks its own.
template <typename Special>
class SpecialsByTarget {
public:
    using Key = Index (*)(const Special&);
    SpecialsByTarget(const std::vector<Special>& specials, Index num_targets, Key key)
        : specials_(specials), has_(std::size_t(num_targets)), key_(key) {
        assert(std::is_sorted(specials.begin(), specials.end(),
                              [key](const Special& a, const Special& b) { return key(a) < key(b); }));
    }
    // Marks targets [t0, t1): their specials are a run of the list.
    void mark(Index t0, Index t1) {
        std::fill(has_.begin() + t0, has_.begin() + t1, std::uint8_t(0));
        for (auto special = first_at_or_after(t0); special != specials_.end() && key_(*special) < t1; ++special)
            has_[std::size_t(key_(*special))] = 1;
    }
    const Special* operator[](Index target) const {
        return has_[std::size_t(target)] ? &*first_at_or_after(target) : nullptr;
    }

private:
    typename std::vector<Special>::const_iterator first_at_or_after(Index target) const {
        return std::lower_bound(specials_.begin(), specials_.end(), target,
                                [this](const Special& s, Index t) { return key_(s) < t; });
    }

    const std::vector<Special>& specials_;
    TransientVector<std::uint8_t> has_;
    Key key_;
};

class FaceVaryingBuilder {
public:
    using Mode = FaceVaryingInterpolation;

    // `base` is the vertex plan's level 0 (full topology, sharpness set).
    FaceVaryingBuilder(const MeshView& mesh, int layer, const Options& options, const LevelState& base);
    // Plans one level: `level` (its features, and its faces and edges unless it was not built: then they are read
    // through `level_parent`, the level before it), the vertex plan's stencils for it, and the child level's features.
    void plan_level(const LevelState& level, const Topology* level_parent, const LevelStencils& vertex_stencils,
                    const LevelState& child, bool last);
    // The limit pass over the last level (`last`: its features), from the vertex plan's limit tables; `rules` decays
    // the sharpness that outlasts the last level.
    void plan_limit(const LimitTables& limit, const LevelState& last, const RuleSet& rules);
    FaceVaryingPlan finish();

private:
    // A value's class on the current level (rules/face_varying_rules.h).
    using Tag = FaceVaryingTag;
    // A part's own lists for its walks around values (the parts of a level run at once on the plan's threads).
    struct Walk {
        std::vector<Index> edges, inner, around;
        std::vector<Tag*> value_tags;
        std::vector<float> parent_edges, child_edges;
    };
    // A part's share of a level's special masks, joined in part order (the order of one part).
    struct alignas(64) PartOutput {  // a cache line apart: each part pushes to its own
        std::vector<SpecialVertex> vertices;
        std::vector<SpecialEdge> edges;
        std::vector<RingWeightedVertex> ring_weighted;  // the limit's: `first` counts in the part's own ring_weights
        std::vector<float> ring_weights;
    };
    // The base level's value -> vertex and layer edge -> edge maps, and its seams, from the faces' corners.
    void map_to_vertices(const LevelState& base);
    // The child level's, from this level's through refine_topology's numbering (`t`: this level's vertex mesh), in
    // `parts` parts.
    void inherit_mapping(const Topology& t, const VertexNeighbourhood& vertex_level, int parts);
    void classify_base(const LevelState& base);
    // What the seam rules read of base vertex v (`values` on it; its sharpness left 0) and of value x's span
    // (face_varying_rules.h).
    FaceVaryingVertex seam_vertex(const Topology& t, Index v, int values, bool non_manifold) const;
    FaceVaryingSpan span_of(Index x, const LevelState& base, bool disjoint, Walk& walk) const;
    // The layer's current level as the queries below read it: its own arrays, or its parent's where it is not built.
    VertexNeighbourhood layer() const {
        return VertexNeighbourhood(values_, values_built_ ? nullptr : &parent_values_);
    }
    // How many parts a level of `items` values and edges is planned in: one where the parts' meetings would cost
    // more than their share.
    int parts_for(std::size_t items) const;
    // The layer edges at value x, into walk.edges.
    const std::vector<Index>& edges_at(Index x, Walk& walk) const;
    // The layer edges at value x with two faces in the layer (inside its span) and their vertex-mesh edges.
    void inner_edges(Index x, std::vector<Index>& edges, Walk& walk) const;
    // The far ends of the layer's boundary edges at x (its seam neighbours); false unless there are exactly two.
    bool seam_ends(Index x, Index ends[2], Walk& walk) const;
    Index neighbour_at_vertex(Index x, Index vertex, Walk& walk) const;  // x's neighbour value lying on `vertex`, or -1
    // A vertex's mask `m` for value x on that vertex: its crease neighbours read through the layer.
    SpecialVertex on_layer(Index x, const SpecialVertex& m, Walk& walk) const;
    // plan_level's steps over a part of the level: the children's tags at vertices [v0, v1) where semi-sharp features
    // decay, the value points of values [x0, x1), the edge points of layer edges [e0, e1) and their children's tags.
    void release_values(const LevelState& level, const LevelState& child, const VertexNeighbourhood& vertex_level,
                        const TransientVector<Index>& offsets, const TransientVector<Index>& at_vertex, Index v0,
                        Index v1, TransientVector<Tag>& child_tags, Walk& walk) const;
    void plan_value_points(const LevelState& level, const LevelState& child, const VertexNeighbourhood& vertex_level,
                           const TransientVector<Index>& offsets, const TransientVector<Index>& at_vertex,
                           const SpecialsByTarget<SpecialVertex>& special_vertex,
                           const TransientVector<Tag>& child_tags, Index x0, Index x1, std::vector<SpecialVertex>& out,
                           Walk& walk) const;
    // The weight of a released value's hold, from the features that decayed in its span or its sibling's.
    float hold_weight(const LevelState& level, const LevelState& child, const VertexNeighbourhood& vertex_level,
                      const TransientVector<Index>& offsets, const TransientVector<Index>& at_vertex, Index x,
                      Walk& walk) const;
    void plan_edge_points(const VertexNeighbourhood& vertex_level, const SpecialsByTarget<SpecialEdge>& special_edge,
                          bool planned_further, Index e0, Index e1, TransientVector<Tag>& child_tags,
                          std::vector<SpecialEdge>& out) const;
    // plan_level's last step: the layer's next level, this level's arrays handed to its tables `s`.
    void refine_values(const Topology& t, const VertexNeighbourhood& vertex_level, LevelStencils& s,
                       bool planned_further, bool child_not_built, int parts);
    // The limit points of values [x0, x1) but the `held` ones (sorted), from the vertex plan's limit masks by vertex.
    void plan_limit_points(const LimitTables& limit, const SpecialsByTarget<SpecialVertex>& special_vertex,
                           const SpecialsByTarget<RingWeightedVertex>& ring_weighted, const SpecialVertex* held,
                           std::size_t num_held, Index x0, Index x1, PartOutput& out) const;
    // Where a value held on the last level goes: held until its features are spent, then along its seam; its steps
    // (face_varying_limit.cpp): a held value, the hold at its vertex, gathered, then refined one level at a time.
    void plan_held_limits(const LevelState& last, const RuleSet& rules, LevelStencils& s) const;
    struct Held;
    struct HeldVertex;
    void gather_held(Index v, const LevelState& last, HeldVertex& at, std::vector<Held>& held, Walk& walk) const;
    void hold_one_level(const RuleSet& rules, HeldVertex& at, Held* first, Held* last) const;

    Options options_;
    FaceVaryingPlan plan_;
    Topology values_;  // the layer's mesh on the current level
    // The level before the last is not built where the vertex plan builds none (no limit surface) and the layer is not
    // linear (whose edges inside faces are special): its tables are filled from its parent, kept here meanwhile.
    bool skip_level_before_last_ = false;
    bool values_built_ = true;
    Topology parent_values_;
    // Up to date for the levels still to be planned (after the last level without a limit surface: partial, stale):
    TransientVector<Tag> tags_;            // per value
    TransientVector<Index> vertex_of_;     // per value: its vertex
    TransientVector<Index> edge_of_;       // per layer edge: its vertex-mesh edge
    TransientVector<std::uint8_t> split_;  // per vertex-mesh edge: a seam (or linear boundary) runs along it
};

}  // namespace loopsub::detail
