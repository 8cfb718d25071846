// The face-varying (UV) seam rules, as pure functions of a summary of a value's neighbourhood: no mesh here. They are
// OpenSubdiv 3.5's: Sdc::Options::FVarLinearInterpolation says which values stay linear, Vtr::FVarLevel's value tags
// (set in FVarLevel::completeTopologyFromFaceValues) how a value at a seam is refined, and
// Vtr::FVarRefinement::reclassifySemisharpValues how those tags change as semi-sharp features decay. The builder
// (plan/face_varying*.cpp) gathers the facts of each vertex and value and asks.
//
// A layer is refined as a mesh of its own, one value per (vertex, value) pair: a value's **span** is its faces at its
// vertex, and a vertex whose faces carry more than one value (or which the mode makes linear) is **mismatched**: its
// values follow the seam rules, not the vertex's.
#pragma once

#include "loopsub/loopsub.h"
#include "rules/rules.h"

namespace loopsub::detail {

// FVAR_LINEAR_BOUNDARIES and FVAR_LINEAR_ALL: seams and boundaries are linear (FVarLevel::_hasLinearBoundaries).
inline bool linear_boundaries(FaceVaryingInterpolation mode) {
    return mode == FaceVaryingInterpolation::Boundaries || mode == FaceVaryingInterpolation::All;
}
// FVAR_LINEAR_CORNERS_PLUS1 and _PLUS2: the two values of a vertex sharpen each other
// (FVarLevel::_hasDependentSharpness).
inline bool dependent_sharpness(FaceVaryingInterpolation mode) {
    return mode == FaceVaryingInterpolation::CornersPlus1 || mode == FaceVaryingInterpolation::CornersPlus2;
}

// A value's class on a level (FVarLevel::ValueTag, reduced to what the masks read). No member initialisers: a level's
// tags are sized uninitialised and written in parts (FaceVaryingTag{} is all false).
struct FaceVaryingTag {
    bool mismatch;    // its vertex has a seam, or the mode makes it linear: the seam rules apply
    bool crease;      // follows the seam as a B-spline; otherwise (mismatched) it stays where it is
    bool semi_sharp;  // held while semi-sharp features around it decay, then a crease
    bool dep_sharp;   // held for its sibling's semi-sharp features (CORNERS_PLUS1/2, two values)
};

// What the seam rules read of a vertex of the base level.
struct FaceVaryingVertex {
    int values;            // the values on it (one per span)
    bool seam;             // a seam runs along one of its edges
    bool boundary;         // one of its edges has a single face
    bool one_face_corner;  // on the boundary with a single face
    bool non_manifold;     // its faces make more than one fan, or an edge of it is non-manifold
    float sharpness;       // its own
};

// What the seam rules read of one value's span: its faces, and the sharpness of the edges inside it (those with a face
// of the span on each side).
struct FaceVaryingSpan {
    int faces = 0;
    int infinite = 0;       // inner edges infinitely sharp
    int semi = 0;           // inner edges semi-sharp
    bool disjoint = false;  // its faces are not one fan, or a seam ends inside it
};

// Whether the values at a vertex follow the seam rules: a seam at it; a boundary under linear boundaries; a corner of
// one face where the mode sharpens corners and the vertex's own boundary rule does not already
// (makeSmoothCornersSharp); a non-manifold vertex with more than one value.
bool face_varying_mismatched(FaceVaryingInterpolation mode, Boundary boundary, const FaceVaryingVertex& vertex);

// The tags of the values at a mismatched vertex (`vertex.values` of them, `spans` one per value, not read at a
// non-manifold vertex), each marked mismatched and then:
//   * it stays (a corner) at a non-manifold vertex, under linear boundaries, at an infinitely sharp vertex, where
//     CORNERS_PLUS1/2 meet three values or more or two of which one spans an infinitely sharp edge or a disjoint span,
//     at a dart (one value, interior) under CORNERS_PLUS2 or linear boundaries, where CORNERS_PLUS2 meets two values
//     one of which spans one face; and, whatever the others, where its own span is disjoint, holds an infinitely sharp
//     edge, or (any mode but None) is a single face;
//   * else it is held (semi_sharp) where its span or the vertex is semi-sharp, or held for its sibling (dep_sharp too)
//     where CORNERS_PLUS1/2 meet two values only one of which spans semi-sharp edges;
//   * else it follows its seam (crease).
void face_varying_base_tags(FaceVaryingInterpolation mode, const FaceVaryingVertex& vertex,
                            const FaceVaryingSpan* spans, FaceVaryingTag* tags);

// The class the API reports for a value's tag.
FaceVaryingValueClass face_varying_value_class(const FaceVaryingTag& tag);

// Whether a layer edge splits into seam halves: it lies on a seam (or linear boundary), or the mode is linear
// everywhere. Its midpoint is then tagged face_varying_midpoint_tag: mismatched, following the seam unless seams are
// linear.
inline bool face_varying_edge_on_seam(FaceVaryingInterpolation mode, bool seam) {
    return seam || mode == FaceVaryingInterpolation::All;
}
inline FaceVaryingTag face_varying_midpoint_tag(FaceVaryingInterpolation mode) {
    return {true, !linear_boundaries(mode), false, false};
}

// Whether held values at a vertex can be released between a level and the next (reclassifySemisharpValues): its
// values' features were semi-sharp on the level, and its own sharpness is spent on the next.
inline bool face_varying_may_release(bool semi_sharp_features, float child_vertex_sharpness) {
    return semi_sharp_features && !is_sharp(child_vertex_sharpness);
}

// FVarRefinement::reclassifySemisharpValues at a vertex whose held values may be released (face_varying_may_release):
// of its `n` values' child tags, a held value turns into a crease unless semi-sharp edges remain at the vertex on the
// next level and it is held for its sibling or `inner_semi(i)` (an edge inside its span is still semi-sharp there).
// Under CORNERS_PLUS1/2 a value held for a sibling that is no longer held is released from that dependence.
template <typename InnerSemi>
void release_held_values(FaceVaryingInterpolation mode, FaceVaryingTag* const* child_tags, int n, bool child_semi_edges,
                         InnerSemi inner_semi) {
    for (int i = 0; i < n; ++i) {
        FaceVaryingTag& tag = *child_tags[i];
        if (!tag.semi_sharp) continue;
        if (child_semi_edges && (tag.dep_sharp || inner_semi(i))) continue;
        tag.crease = true;
        tag.semi_sharp = tag.dep_sharp = false;
    }
    if (n == 2 && dependent_sharpness(mode)) {
        FaceVaryingTag& first = *child_tags[0];
        FaceVaryingTag& second = *child_tags[1];
        if (first.dep_sharp && !second.semi_sharp) first.dep_sharp = false;
        else if (second.dep_sharp && !first.semi_sharp) second.dep_sharp = false;
    }
}

// Whose span's decay weighs the release of value i of n (the transition weight): its own, or its sibling's where it
// was held for the sibling.
inline int face_varying_weight_span(const FaceVaryingTag& tag, int i, int n) {
    return tag.dep_sharp && n == 2 ? 1 - i : i;
}

// Whether a mismatched value follows its seam from this level on: its child's tag is a crease and it has two seam
// neighbours (`seam_ends()`, asked only then). One that does not stays where it is.
template <typename SeamEnds>
bool face_varying_follows_seam(const FaceVaryingTag& child_tag, SeamEnds seam_ends) {
    return child_tag.crease && seam_ends();
}
// The mask of a mismatched value that follows its seam on the next level (its child's tag a crease, two seam
// neighbours): the seam's crease mask (1, 6, 1) / 8; a value that was held (semi_sharp) blends the hold (a corner) in
// by `hold_weight`, Sdc's transition weight of what decayed in its weight span.
VertexMask face_varying_seam_mask(bool held, double hold_weight);

// Where a value of the last level goes at the limit (Far::PrimvarRefiner::LimitFaceVarying).
enum class FaceVaryingLimit {
    Stays,  // linear everywhere, or mismatched and not following a seam of two neighbours: where it is
    Seam,   // on its seam's B-spline: crease_limit_mask over its two seam neighbours
    Vertex  // its vertex's own limit, read through the layer
};
// `seam_ends()`: whether the value has exactly two seam neighbours, asked only of a mismatched value that follows its
// seam.
template <typename SeamEnds>
FaceVaryingLimit face_varying_limit(FaceVaryingInterpolation mode, const FaceVaryingTag& tag, SeamEnds seam_ends) {
    if (mode == FaceVaryingInterpolation::All || (tag.mismatch && (!tag.crease || !seam_ends())))
        return FaceVaryingLimit::Stays;
    return tag.mismatch ? FaceVaryingLimit::Seam : FaceVaryingLimit::Vertex;
}
// A value held past the last level: its seam's limit once released, the corner's where it is held for good.
LimitMask face_varying_held_limit_mask(bool released);

// The tags a value carries on a tessellation's layer mesh (its input level as a mesh of its own, whose seams are its
// boundary and whose crease rule is the seams' B-spline), so that the mesh's own rules refine it as its class says:
// a value that stays is an infinitely sharp corner; one without a seam takes its vertex's tags (its corner sharpness,
// its cone, and a corner of one face that VTX_BOUNDARY_EDGE_AND_CORNER keeps); one held by semi-sharp features takes
// its vertex's sharpness (its span's edges carry theirs); one on a seam none.
struct FaceVaryingLayerTag {
    float sharpness;  // as a corner tag: 0 for none
    bool cone;
};
FaceVaryingLayerTag face_varying_layer_tag(FaceVaryingValueClass value_class, float vertex_corner_sharpness,
                                           bool vertex_cone, bool vertex_kept_corner);

}  // namespace loopsub::detail
