// What a Plan holds once built: the product of PlanBuilder (plan_builder.h). The tables the kernels read each frame,
// the output connectivity and tags, and the per-level facts the API reports; then the scratch an evaluation reuses
// and the copies made on a first request. plan.cpp answers the API from it; evaluate.cpp and limit.cpp run it.
#pragma once

#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "plan/face_varying.h"
#include "base/large_allocator.h"
#include "loopsub/loopsub.h"
#include "tables/stencils.h"
#include "topology/topology.h"

namespace loopsub {

namespace detail {

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
        Index own;  // where its tangent weights are its own (own_t1 / _t2, one per point), else -1
    };
    std::vector<Side> sides;
    std::vector<Index> side_points;
    // The corners that take a side's normal: (output corner 3 t + k, side), sorted by corner. The others take their
    // vertex's, so the plan keeps no index per corner (Plan::corner_normal_indices makes them on a first request).
    std::vector<std::pair<Index, Index>> corner_sides;
    // Tangent weights: smooth by valence (p_0 .. p_{n-1}), sides by face count (vertex, p_0 .. p_faces).
    std::vector<std::vector<float>> smooth_t1, smooth_t2, side_t1, side_t2;
    // Where semi-sharp features outlast the last level, the tangent masks that apply once they are spent, pulled back
    // to the last level: weights per point of a vertex's ring (own_vertex_tangents: (vertex, first), sorted) or of a
    // side (Side::own). Their vertex's weight is what the points' leave, as in the tables above.
    std::vector<float> own_t1, own_t2;
    std::vector<std::pair<Index, Index>> own_vertex_tangents;
};

// The output's tags (Plan::output_crease_edges and the rest): edges as vertex pairs, a value per edge or vertex.
struct OutputTags {
    std::vector<Index> crease_edges, corner_vertices, sharp_edges;
    std::vector<float> crease_sharpness, corner_sharpness, sharp_edge_sharpness;
};

}  // namespace detail

using detail::Index;

struct PlanImpl {
    explicit PlanImpl(const Options& options);  // sizes the copies made on request

    Options options;
    Kernel kernel = Kernel::Scalar;  // resolved
    int num_input_vertices = 0;
    int num_input_triangles = 0;
    std::vector<int> level_num_vertices;  // the input's, then each level's

    // What the kernels read: a level's tables per level (their four forms: LevelStencils), then the limit's pass;
    // each face-varying layer's own.
    std::vector<detail::LevelStencils> stencils;
    std::unique_ptr<detail::LimitTables> limit;         // with Options::limit_surface
    std::vector<detail::FaceVaryingPlan> face_varying;  // per MeshView::face_varying layer
    // A kernel sums up to this many input values before it weights them (a vertex's ring): inputs must stay below
    // the float maximum divided by it, or the sums overflow to infinity and give NaN (checked by evaluate).
    int max_summed_terms = 1;

    // The output mesh.
    detail::LargeVector<Index> output_triangles;
    std::vector<std::uint8_t> holes;            // per input triangle (empty: none)
    detail::LargeVector<Index> kept_triangles;  // with holes: the last level's triangles written, in order
    detail::OutputTags output_tags;
    // Each level's vertex classes, in pooled arrays. The last level's (an entry per output vertex) are kept only where
    // they are not Smooth, as (vertex, class), unless the limit surface classified them: only tagging a result asks
    // for them, and filling a whole array costs a plan time (docs/benchmark.md, "Measurements behind the code").
    std::vector<detail::LargeVector<VertexType>> level_vertex_types;
    std::vector<std::pair<Index, VertexType>> last_level_types;
    double topology_ms = 0.0;

    // What an evaluation writes besides its output, kept for the next (Plan::evaluate is not reentrant).
    struct Frame {
        detail::LargeVector<float> scratch[2];  // the passes' sources and targets, in turn (run_passes)
        std::vector<float> normals;             // the compact limit normals, for the per-corner evaluate to gather from
        // run_passes' lists, kept so that a frame allocates nothing once the plan has run one of each kind.
        std::vector<const detail::LevelStencils*> passes;
        std::vector<int> counts;
        std::vector<ChannelsView<const float>> sources;
        std::vector<ChannelsView<float>> targets;
        double evaluate_ms = 0.0;
    };
    Frame frame;

    // Made on a first request, safe from several threads: only tests and tools that map vertices across levels or
    // tag a result ask for them.
    struct Copies {
        std::vector<std::vector<Index>> level_edges;
        std::vector<std::once_flag> level_edges_ready;
        std::vector<std::vector<VertexType>> level_vertex_types;
        std::vector<std::once_flag> level_vertex_types_ready;
        detail::LargeVector<Index> output_parents;
        std::once_flag output_parents_ready;
        detail::LargeVector<Index> corner_normals;  // Plan::corner_normal_indices
        std::once_flag corner_normals_ready;
    };
    mutable Copies copies;

    // The compact limit normals (Plan::num_limit_normals of them, 3 floats each) of the last level's points
    // `last_level` (its first three channels; an element's channels side by side, as in the evaluation's scratch).
    // limit.cpp.
    void limit_normals(ChannelsView<const float> last_level, float* normals);
};

}  // namespace loopsub
