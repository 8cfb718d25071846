// What a Plan holds once built: the stencil tables the kernels read each frame, the output connectivity and tags,
// and the per-level facts the API reports. plan.cpp builds it, evaluate.cpp runs it.
#pragma once

#include <memory>
#include <mutex>
#include <vector>

#include "large_allocator.h"
#include "loopsub/loopsub.h"
#include "rule_set.h"
#include "stencils.h"
#include "topology.h"

namespace loopsub {

namespace detail {
struct LevelState;  // one level while the plan is built (plan.cpp)
}  // namespace detail

using detail::Index;

struct PlanImpl {
    Options options;
    std::unique_ptr<detail::RuleSet> rules;  // while building
    Kernel kernel = Kernel::Scalar;
    int num_input_vertices = 0;
    int num_input_triangles = 0;
    std::vector<int> level_num_vertices;
    // Computed on first request: only tests and tools that map vertices across levels ask for them.
    mutable std::vector<std::vector<Index>> level_edges;
    mutable std::vector<std::once_flag> level_edges_ready;
    std::vector<std::vector<VertexType>> level_vertex_types;
    std::vector<detail::LevelStencils> stencils;
    detail::LargeVector<Index> output_triangles;
    mutable detail::LargeVector<Index> output_parents;  // on first request
    mutable std::once_flag output_parents_ready;
    std::vector<Index> output_crease_edges, output_corner_vertices;
    std::vector<float> output_crease_sharpness, output_corner_sharpness;
    std::vector<Index> cones;  // Hoppe94: the vertices tagged as cones, sorted
    detail::LargeVector<float> scratch[2];
    // A kernel sums up to this many input values before it weights them (a vertex's ring): inputs must stay below
    // the float maximum divided by it, or the sums overflow to infinity and give NaN (checked by evaluate).
    int max_summed_terms = 1;
    double topology_ms = 0.0, evaluate_ms = 0.0;

    // Building (plan.cpp).
    void build(const MeshView& mesh);
    detail::LevelState base_level(const MeshView& mesh);
    // Classifies level L's vertices and edges, fills its stencils, and returns the child level's sharpness.
    void plan_level(detail::LevelState& level, const detail::Topology& parent, detail::LevelState& child, int child_level);
    void collect_output_tags(const detail::LevelState& last);
};

}  // namespace loopsub
