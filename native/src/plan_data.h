// What a Plan holds once built: the stencil tables the kernels read each frame, the output connectivity and tags,
// and the per-level facts the API reports. plan.cpp builds it, evaluate.cpp runs it.
#pragma once

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "face_varying.h"
#include "large_allocator.h"
#include "loopsub/loopsub.h"
#include "rule_set.h"
#include "stencils.h"
#include "topology.h"

namespace loopsub {

namespace detail {
struct LevelState;  // one level while the plan is built (level_state.h)

// The limit surface (Options::limit_surface, limit.cpp): one more vertex-only pass over the last level, and the
// tables of the limit normals.
struct LimitTables {
    // Limit positions: the kernels' vertex masks (num_edges == 0). Where a vertex's fan is a disk of smooth edges
    // its ring is in counter-clockwise order, as the smooth tangent masks read it.
    LevelStencils positions;
    // Vertices whose corners take the normal of their side of a crease (crease and corner rules, or a fan that is
    // not a disk): 1 per such vertex.
    std::vector<std::uint8_t> by_side;
    // A side: `faces` faces counter-clockwise around `vertex`, through points side_points[first ..]: faces + 1 of
    // them from the leading to the trailing sharp edge, or `faces` of them for a closed fan.
    struct Side {
        Index vertex, first;
        int faces;
        bool closed;
    };
    std::vector<Side> sides;
    std::vector<Index> side_points;
    std::vector<std::pair<Index, Index>> corner_sides;  // (output corner 3 t + k, side), sorted by corner
    // Tangent weights: smooth by valence (p_0 .. p_{n-1}), sides by face count (vertex, p_0 .. p_faces).
    std::vector<std::vector<float>> smooth_t1, smooth_t2, side_t1, side_t2;
    std::vector<float> vertex_normals, side_normals;  // scratch of the normals pass
};
}  // namespace detail

using detail::Index;

struct PlanImpl {
    Options options;
    std::unique_ptr<detail::RuleSet> rules;  // while building
    // While building, past the first split: the base level's faces and edge faces, for the walks around base vertices
    // (VertexNeighbourhood); the stencils' own copy where they keep the base whole (derived tables).
    detail::Topology kept_base;
    const detail::Topology* base_for_walks = nullptr;
    Kernel kernel = Kernel::Scalar;
    int num_input_vertices = 0;
    int num_input_triangles = 0;
    std::vector<int> level_num_vertices;
    // Computed on first request: only tests and tools that map vertices across levels ask for them.
    mutable std::vector<std::vector<Index>> level_edges;
    mutable std::vector<std::once_flag> level_edges_ready;
    // Each level's vertex classes, in pooled arrays; the copies Plan::level_vertex_types returns are made on first
    // request. The last level's (an entry per output vertex) are kept only where they are not Smooth, as (vertex,
    // class), unless the limit surface classified them: filling its array took 23-26 us of a 2.1 ms two-thread plan,
    // and only tagging a result asks for it.
    std::vector<detail::LargeVector<VertexType>> level_vertex_types;
    std::vector<std::pair<detail::Index, VertexType>> last_level_types;
    mutable std::vector<std::vector<VertexType>> level_vertex_types_copies;
    mutable std::vector<std::once_flag> level_vertex_types_ready;
    std::vector<detail::LevelStencils> stencils;
    std::unique_ptr<detail::LimitTables> limit;  // with Options::limit_surface
    std::vector<detail::FaceVaryingPlan> face_varying;  // per MeshView::face_varying layer
    detail::LargeVector<Index> output_triangles;
    std::vector<std::uint8_t> holes;               // per input triangle (empty: none)
    detail::LargeVector<Index> kept_triangles;     // with holes: the last level's triangles written, in order
    mutable detail::LargeVector<Index> output_parents;  // on first request
    mutable std::once_flag output_parents_ready;
    std::vector<Index> output_crease_edges, output_corner_vertices, output_sharp_edges;
    std::vector<float> output_sharp_edge_sharpness;
    std::vector<float> output_crease_sharpness, output_corner_sharpness;
    std::vector<Index> cones;  // Hoppe94: the vertices tagged as cones, sorted
    detail::LargeVector<float> scratch[2];
    // A kernel sums up to this many input values before it weights them (a vertex's ring): inputs must stay below
    // the float maximum divided by it, or the sums overflow to infinity and give NaN (checked by evaluate).
    int max_summed_terms = 1;
    // The level before the last is never built where there is no limit surface to plan over two levels or more: its
    // stencil tables come from its parent's connectivity (filled here, or derived as an evaluation runs), and the last
    // level's triangles straight from its parent too (write_grandchild_faces). Face-varying layers read its edges
    // through its parent (FaceVaryingBuilder::plan_level).
    bool skip_level_before_last = false;
    // Options::level_tables, resolved: the stencils of levels 1 .. levels - 1 are derived (LevelStencils::derived_from).
    bool derive_tables = false;
    double topology_ms = 0.0, evaluate_ms = 0.0;

    // Building (plan.cpp).
    void build(const MeshView& mesh);
    detail::LevelState base_level(const MeshView& mesh);
    // Classifies level L's vertices and edges, fills its stencils, and returns the child level's sharpness.
    void plan_level(detail::LevelState& level, const detail::Topology& parent, detail::LevelState& child, int child_level);
    void collect_output_tags(const detail::LevelState& last);
    // Leaves the descendants of hole triangles out of everything indexed by output triangle.
    void drop_holes();
    // The limit's stencils and normal tables for the last level (limit.cpp).
    void plan_limit(detail::LevelState& last, const detail::Topology& parent);
    // Per output corner, the limit normal of the last level's points `last_level` (its first three channels; an
    // element's channels side by side, as in the evaluation's scratch).
    void limit_normals(ChannelsView<const float> last_level, float* corner_normals);
};

}  // namespace loopsub
