// The rules layer's interface to the plan builder (OpenSubdiv's Sdc::Scheme in spirit): every decision of the
// subdivision rules, each in one place. What both rule sets share is here (the sharpness the topology imposes on the
// base level); what differs is virtual: how tags become sharpness, how sharpness decays from level to level, which
// mask a vertex point, an edge point and a limit point take. The masks and the vertex classes themselves are the pure
// functions of rules.h. The builder gathers the local quantities (connectivity, sharpness, classes) and asks.
#pragma once

#include <memory>
#include <vector>

#include "loopsub/loopsub.h"
#include "rules/rules.h"

namespace loopsub::detail {

// A vertex as the builder has classified it on one level.
struct VertexSituation {
    VertexType type;  // Hoppe 94's class (hoppe94_vertex_type); OpenSubdiv's rule is `rule`
    SdcRule rule;     // from the vertex's own sharpness and its sharp-edge count
    int valence;
    float sharpness, child_sharpness;  // the vertex's own, on this level and the next
    // Per incident edge, in ring order: sharpness on this level and of its half on the next.
    const float* edge_sharpness;
    const float* child_edge_sharpness;
    int num_child_sharp_edges;
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

// A vertex's 1-ring on the last level, as the rules read it on the levels the refinement would go on to: slot 0 is the
// vertex, slot 1 + k the other end of its k-th edge. Each level keeps the ring's shape (the vertex point and the edge
// points of its edges are the next level's ring), so the ring alone says where the vertex goes.
struct RingSituation {
    int valence;
    float vertex_sharpness;
    const float* edge_sharpness;      // per edge
    const float* far_half_sharpness;  // per edge: on the next level, the sharpness of its half at its other end
    const int* face_count;            // per edge
    const std::int32_t* wings;        // 2 per edge: the slots of its wings C and D
};

// The ring refined until no semi-sharp feature is left at the vertex: `refinement` ((n + 1)^2, row-major) takes the
// ring's points to theirs `levels` levels down, where the vertex has only smooth and infinitely sharp features left,
// and its rule and crease edges (the first two sharp edges, -1: none) are the ones its limit masks follow.
struct SpentRing {
    std::vector<double> refinement;
    int levels = 0;
    SdcRule rule = SdcRule::Smooth;
    int crease[2] = {-1, -1};
};

class RuleSet {
public:
    explicit RuleSet(Boundary boundary) : boundary_(boundary) {}
    virtual ~RuleSet() = default;

    // ---- Shared by both rule sets (Far's prepareComponentTagsAndSharpness for OpenSubdiv) ----
    // An edge's sharpness on the base level: boundary and non-manifold edges are infinitely sharp, whatever their tag.
    float base_edge_sharpness(float tag, int face_count, bool non_manifold) const {
        if (face_count < 2 || non_manifold) return kInfiniteSharpness;
        return tag == 0.0f ? 0.0f : edge_sharpness_from_tag(tag);
    }
    // A vertex's on the base level: infinitely sharp where it is non-manifold, unless it sits on exactly two edges
    // with more than two faces (a non-manifold crease; OpenSubdiv 3.5 does not count edges that are non-manifold by
    // their winding alone), and, with Boundary::EdgesAndCorners, where it is a boundary vertex with a single face.
    // `count_faces()` gives {the sum of its edges' face counts, its edges with more than two faces}; it is called
    // only where the cheaper facts leave the answer open (most vertices are regular and untagged).
    template <typename CountFaces>
    float base_vertex_sharpness(float tag, bool non_manifold, int valence, CountFaces count_faces) const {
        const bool corners_kept = boundary_ == Boundary::EdgesAndCorners;
        if (non_manifold || (corners_kept && valence == 2)) {
            const auto [edge_faces, fins] = count_faces();
            if (corners_kept && valence == 2 && edge_faces == 2) return kInfiniteSharpness;
            if (non_manifold && fins != 2) return kInfiniteSharpness;
        }
        return tag == 0.0f ? 0.0f : vertex_sharpness_from_tag(tag);
    }
    // Boundary::None: a boundary edge that its tag does not make infinitely sharp takes every face at its two ends
    // out of the surface.
    bool boundary_edge_removes_faces(float tag, int face_count) const {
        return face_count == 1 && boundary_ == Boundary::None && !is_infinite(edge_sharpness_from_tag(tag));
    }

    // ---- Where the rule sets differ ----
    virtual bool has_cones() const = 0;
    // Sharpness of a tagged edge or vertex on the base level (boundaries and non-manifold features come on top); asked
    // of nonzero tags only, a zero tag being zero sharpness under every rule set.
    virtual float edge_sharpness_from_tag(float tag) const = 0;
    virtual float vertex_sharpness_from_tag(float tag) const = 0;
    // One level down: the half of an edge at a vertex, given the sharpness of every edge there; a vertex.
    virtual float child_edge_sharpness(float sharpness, const float* at_vertex, int count) const = 0;
    virtual float child_vertex_sharpness(float sharpness) const = 0;
    // Whether child_edge_sharpness reads the other edges at the vertex (Chaikin), or only the edge's own sharpness.
    virtual bool decay_reads_other_edges() const = 0;
    // The tag a child carries into the output, so that refining the output goes on where this refinement stops.
    virtual float child_tag(float tag, float child_sharpness) const = 0;
    // The vertex point's mask; `ends` receives the edges its crease neighbours lie on (when mask.crease != 0).
    virtual VertexMask vertex_mask(const VertexSituation& vertex, std::int32_t ends[2]) const = 0;
    // The edge point's mask, for a sharp edge (smooth edges take smooth_edge_mask()).
    virtual EdgeMask edge_mask(const EdgeSituation& edge) const = 0;
    // Where a vertex of the last level lies on the limit surface; end_a / end_b weight the other ends of
    // vertex.crease[0] / [1]. `vertex_weight_a` / `_b`: the vertex's weight in the edge points of those two edges.
    virtual LimitMask limit_mask(const VertexSituation& vertex, double vertex_weight_a,
                                 double vertex_weight_b) const = 0;

    // Refines a vertex's ring by the masks above, level after level, until its semi-sharp features are spent.
    SpentRing refine_until_spent(const RingSituation& ring) const;

private:
    Boundary boundary_;
};

std::unique_ptr<RuleSet> make_rule_set(const Options& options);

}  // namespace loopsub::detail
