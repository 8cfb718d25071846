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
#include "tables/limit_tables.h"
#include "tables/stencils.h"
#include "topology/topology.h"

namespace loopsub {

namespace detail {

// The output's tags (Plan::output_crease_edges and the rest): edges as vertex pairs, a value per edge or vertex.
struct OutputTags {
    std::vector<Index> crease_edges, corner_vertices, sharp_edges;
    std::vector<Index> crease_edge_indices, sharp_edge_indices;  // the last level's edge numbers
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
    // Each input triangle's edges in the base level's numbering (3 per triangle, edge k from corner k to k + 1), for
    // plans of at least one level: what names an output edge's input edge (Plan::output_edge_parents).
    detail::LargeVector<Index> input_triangle_edges;
    std::vector<std::uint8_t> holes;            // per input triangle (empty: none)
    detail::LargeVector<Index> kept_triangles;  // with holes: the last level's triangles written, in order
    detail::OutputTags output_tags;
    // Each level's vertex classes, in pooled arrays. The last level's (an entry per output vertex) are kept only where
    // they are not Smooth, as (vertex, class), unless the limit surface classified them: only tagging a result asks
    // for them, and filling a whole array costs a plan time (docs/benchmark.md, "Measurements behind the code").
    std::vector<detail::LargeVector<VertexType>> level_vertex_types;
    std::vector<std::pair<Index, VertexType>> last_level_types;
    double topology_ms = 0.0;
    std::vector<InputProblem> notes;  // Plan::notes: what the input's checks found to tell, no error

    // What an evaluation writes besides its output, kept for the next (Plan::evaluate is not reentrant).
    struct Frame {
        detail::LargeVector<float> scratch[2];  // the passes' sources and targets, in turn (run_passes)
        detail::LargeVector<float> normals;     // the compact limit normals, for the per-corner evaluate to gather from
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
};

}  // namespace loopsub
