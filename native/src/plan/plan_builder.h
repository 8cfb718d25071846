// Building a Plan: all topology work for N levels, done once (the per-frame work is evaluate.cpp's). The builder holds
// what only building needs and fills a PlanImpl, the product (plan_data.h), step by step:
//   base_level           the input's connectivity and features: sharpness from the tags and the topology (the rules)
//   check_memory         the estimate against Options::memory_limit_bytes and 32-bit indices
//   choose_table_forms   which form each level's tables take (LevelStencils, stencils.h)
//   per level, plan_level:
//     start_tables             the level's tables: counts and the smooth masks by valence
//     plan_feature_vertices    around the features only: vertex classes, vertex masks, the child's features
//     classify_last_midpoints  the classes of the last level's midpoints on sharp edges
//     refine_child             the child's connectivity, in the least form its use needs
//     plan_edge_masks          the masks of sharp edges
//     hand_over_tables         the level's arrays the tables keep, moved rather than copied
//   then retire_parent: the level before, done with, gives its arrays to the tables that read them
//   plan_limit_rings     where the limit's rings come from the last level's grandparent: its own (limit.cpp)
//   plan_limit           the limit pass and the normals' tables (limit.cpp)
//   drop_holes, collect_output_tags
// Every rule decision is the rule set's (rule_set.h, rules.h): the builder gathers the local facts and asks.
#pragma once

#include <algorithm>
#include <memory>
#include <vector>

#include "plan/budget.h"
#include "plan/level_state.h"
#include "plan/plan_data.h"
#include "rules/rule_set.h"

namespace loopsub::detail {

class PlanBuilder {
public:
    // Validates the options and the mesh (InputError), checks the memory estimate (MemoryLimitError) and builds.
    static std::unique_ptr<PlanImpl> build(const MeshView& mesh, const Options& options);

private:
    struct Step;
    struct PartOutput;
    struct HalvesOfFeatures;
    struct ChildOfVertex;

    PlanBuilder(const MeshView& mesh, PlanImpl& plan);
    void run();

    LevelState base_level();
    // Returns the bytes the plan is estimated to need.
    std::uint64_t check_memory(const Topology& base) const;
    void choose_table_forms(const LevelState& base, bool face_varying_layers);
    LevelCounts base_counts(const Topology& base) const;

    void plan_level(LevelState& level, const Topology& parent, LevelState& child, int child_level);
    LevelStencils& start_tables(const VertexNeighbourhood& around, int num_vertices);
    void plan_feature_vertices(Step& step, HalvesOfFeatures& halves) const;
    ChildOfVertex decay_into_child(const Step& step, const FeatureVertex& vertex, PartOutput& out,
                                   HalvesOfFeatures& halves) const;
    void add_vertex_mask(const Step& step, const FeatureVertex& vertex, SdcRule rule, const ChildOfVertex& child,
                         std::vector<SpecialVertex>& specials) const;
    void join_parts(Step& step, std::vector<PartOutput>& parts, const HalvesOfFeatures& halves) const;
    void classify_last_midpoints(const Step& step, const HalvesOfFeatures& halves) const;
    void refine_child(Step& step) const;
    void plan_edge_masks(Step& step, const HalvesOfFeatures& halves) const;
    void hand_over_tables(Step& step) const;
    void retire_parent(Topology& parent, int level);

    // limit.cpp
    struct Spent {
        Index vertex;
        std::vector<Index> neighbours;  // slot 1 + k: the other end of its k-th edge
        SpentRing ring;
        // Spent into OpenSubdiv's dart, whose sharp edge refines as a crease's: its limit is the dart's own
        // (plan_darts).
        bool dart = false;
        int slot(Index x) const {
            if (x == vertex) return 0;
            const auto found = std::find(neighbours.begin(), neighbours.end(), x);
            return found == neighbours.end() ? -1 : int(found - neighbours.begin()) + 1;
        }
    };
    // `parent`: the last level's, or its grandparent where the limit's rings come from it
    // (LimitTables::from_grandparent).
    void plan_limit(LevelState& last, const Topology& parent);
    // plan_limit's steps: the feature vertices visited (a part's findings: LimitVisit), their masks, their sides.
    struct LimitVisit;
    void visit_limit_vertices(const LevelState& level, const VertexNeighbourhood& around, bool sides_in_visit,
                              LargeVector<VertexType>& types, std::vector<LimitVisit>& visited);
    std::vector<std::pair<Index, Index>> plan_limit_masks(const std::vector<LimitVisit>& visited,
                                                          const VertexNeighbourhood& around,
                                                          const LargeVector<VertexType>& types, LevelStencils& s) const;
    std::vector<Index> plan_limit_sides(std::vector<LimitVisit>& visited, bool sides_in_visit,
                                        const VertexNeighbourhood& around,
                                        const std::vector<std::pair<Index, Index>>& infinite_at,
                                        const LargeVector<VertexType>& types, Index nv);
    void plan_limit_rings(Topology& grandparent);
    Spent spend(const LevelState& level, const VertexNeighbourhood& around, const FeatureVertex& vertex,
                std::vector<Index>& far_edges, std::vector<float>& far_sharpness) const;
    void plan_darts(const std::vector<std::pair<Index, Index>>& darts, LimitTables& lt) const;
    void pull_back_spent(const std::vector<Spent>& spent, LimitTables& limit) const;
    void drop_holes();
    void collect_output_tags(const LevelState& last);

    const MeshView& mesh_;
    PlanImpl& plan_;
    const Options& options_;  // the plan's
    std::unique_ptr<RuleSet> rules_;
    std::vector<Index> cones_;  // Hoppe94: the vertices tagged as cones, sorted
    // Past the first split: the base level's faces and edge faces, for the walks around base vertices
    // (VertexNeighbourhood); the tables' own copy where they keep the base whole (derived tables).
    Topology kept_base_;
    const Topology* base_for_walks_ = nullptr;
    // The table forms (choose_table_forms; LevelStencils explains them). skip_level_before_last_: the level before
    // the last is not built, its tables are filled from its parent. derive_tables_: Options::level_tables resolved,
    // the tables of levels 1 .. levels - 1 are derived as an evaluation runs.
    bool skip_level_before_last_ = false;
    bool derive_tables_ = false;
    // A plan with the limit surface over two levels or more (no holes): the level before the last is skipped as
    // without the limit, and the limit pass's rings come from the last level's grandparent
    // (LimitTables::from_grandparent). With tags, boundaries or non-manifold places (features all), plan_limit reads
    // the last level's vertices next to them through the level before the last, itself read through the grandparent.
    bool limit_from_grandparent_ = false;
    // Every base edge in two faces that wind against each other, and so every edge of every level.
    bool closed_ = false;
};

}  // namespace loopsub::detail
