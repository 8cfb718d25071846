// The decisions in which the two rule sets differ, each in one place (OpenSubdiv's Sdc::Scheme in spirit): how tags
// become sharpness, how sharpness decays from level to level, which mask a vertex point and an edge point take. The
// plan builder asks these and owns everything the rule sets share (connectivity, boundaries and non-manifold
// features, classification by sharp-edge count, the stencil tables).
#pragma once

#include <memory>

#include "loopsub/loopsub.h"
#include "rules.h"

namespace loopsub::detail {

// A vertex as the builder has classified it on one level.
struct VertexSituation {
    VertexType type;  // Hoppe94's class (RULES.md section 1); OpenSubdiv's rule is `rule`
    SdcRule rule;     // from the vertex's own sharpness and its sharp-edge count
    int valence;
    float sharpness, child_sharpness;  // the vertex's own, on this level and the next
    // Per incident edge, in ring order: sharpness on this level and of its half on the next.
    const float* edge_sharpness;
    const float* child_edge_sharpness;
    int child_sharp_edges;
    // The first two sharp edges, on this level and the next (-1: none); the mask's crease neighbours lie on them.
    std::int32_t crease[2], child_crease[2];
};

// An edge on one level, for its edge point.
struct EdgeSituation {
    float sharpness;
    VertexType type_a, type_b;  // its ends' classes
    int face_count;
    bool halves_sharp;  // both halves are sharp on the next level
};

class RuleSet {
public:
    virtual ~RuleSet() = default;

    virtual bool has_cones() const = 0;
    // Sharpness of a tagged edge or vertex on the base level (boundaries and non-manifold features come on top); a
    // zero tag is always zero sharpness (the base level passes untagged edges and vertices over).
    virtual float edge_sharpness_from_tag(float tag) const = 0;
    virtual float vertex_sharpness_from_tag(float tag) const = 0;
    // One level down: the half of an edge at a vertex, given the sharpness of every edge there; a vertex.
    virtual float child_edge_sharpness(float sharpness, const float* at_vertex, int count) const = 0;
    virtual float child_vertex_sharpness(float sharpness) const = 0;
    // The tag a child carries into the output, so that refining the output goes on where this refinement stops.
    virtual float child_tag(float tag, float child_sharpness) const = 0;
    // The vertex point's mask; `ends` receives the edges its crease neighbours lie on (when mask.crease != 0).
    virtual VertexMask vertex_mask(const VertexSituation& vertex, std::int32_t ends[2]) const = 0;
    // The edge point's mask, for a sharp edge (smooth edges take smooth_edge_mask()).
    virtual EdgeMask edge_mask(const EdgeSituation& edge) const = 0;
    // Where a vertex of the last level lies on the limit surface; end_a / end_b weight the other ends of
    // vertex.crease[0] / [1]. `vertex_weight_a` / `_b`: the vertex's weight in the edge points of those two edges.
    virtual LimitMask limit_mask(const VertexSituation& vertex, double vertex_weight_a, double vertex_weight_b) const = 0;
};

std::unique_ptr<RuleSet> make_rule_set(const Options& options);

}  // namespace loopsub::detail
